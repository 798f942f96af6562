# The harness of a student's Python file, inside the operating-system sandbox (see
# `server/src/sandbox/native`). It does not grade and it does not run the exercise's loop:
# the harness in JavaScript does both, outside the sandbox, and asks this one for each call
# of a student function, one JSON object a line each way (an empty line after each
# request, which is skipped):
#
#   first line      {"source": ..., "file": "ekf_localization.py", "functions": [...]}
#                   answered {"ready": true} once NumPy is imported
#   {"load": true}  the file evaluated afresh (a fresh copy of its functions):
#                   {"defined": [names of its top-level functions]} or {"error": text}
#   {"call": name, "args": [{"value": ...}, ...]}
#                   {"output": value} or {"error": text}
#
# Arguments arrive as JSON (numbers JSON has none for as the strings "Infinity",
# "-Infinity" and "NaN") and reach the student's function as NumPy arrays: a vector as a
# 1-D array, a matrix as a 2-D array, a list of equal arrays stacked. What it returns goes
# back as JSON: arrays as nested lists, a tuple as the contract's named fields when the
# contract's output has that many ("functions": `Exercise::interface`), numbers JSON cannot hold as the
# strings. Nothing here is trusted by the grader: whatever the student's code does to this
# process, all it can change is what its own functions answer.
import json
import math
import os
import sys
import traceback

import numpy

# Replies go to the descriptor stdout had; what the student's code prints goes nowhere
# (at once: a pipe someone must read would make a printing loop wait rather than run).
REPLIES = os.fdopen(os.dup(1), "w", encoding="utf-8")
NOWHERE = os.open(os.devnull, os.O_WRONLY)
os.dup2(NOWHERE, 1)
sys.stdout = open(NOWHERE, "w", closefd=False)

# The most values a call may return (the JavaScript harness checks again).
MAX_VALUES = 2000
NON_FINITE = {"Infinity": math.inf, "-Infinity": -math.inf, "NaN": math.nan}


def reply(message):
    REPLIES.write(json.dumps(message, allow_nan=False) + "\n")
    REPLIES.flush()


def argument(value):
    """A JSON argument as the student's function gets it."""
    if isinstance(value, str):
        return NON_FINITE.get(value, value)
    if isinstance(value, dict):
        return {key: argument(item) for key, item in value.items()}
    if isinstance(value, list):
        items = [argument(item) for item in value]
        try:
            array = numpy.array(items)
        except ValueError:
            return items
        if array.dtype.kind in "biuf":
            return array
        return items
    return value


class Unsendable(Exception):
    pass


def number(value):
    if math.isfinite(value):
        return value
    return "NaN" if math.isnan(value) else ("Infinity" if value > 0 else "-Infinity")


def output(value, budget):
    """What the student's function returned, as JSON data."""
    budget[0] -= 1
    if budget[0] < 0:
        raise Unsendable(f"returned more than {MAX_VALUES} values")
    if isinstance(value, numpy.ndarray):
        if value.size > MAX_VALUES:
            raise Unsendable(f"returned an array of {value.size} values, "
                             f"more than the {MAX_VALUES} a call may return")
        if value.dtype.kind not in "biuf":
            raise Unsendable(f"returned an array of {value.dtype}, not of numbers")
        return output(value.tolist(), budget)
    if isinstance(value, numpy.generic):
        return output(value.item(), budget)
    if isinstance(value, bool) or value is None or isinstance(value, str):
        return value
    if isinstance(value, int):
        return value if abs(value) < 2**53 else float(value)
    if isinstance(value, float):
        return number(value)
    if isinstance(value, (list, tuple)):
        return [output(item, budget) for item in value]
    if isinstance(value, dict):
        return {str(key): output(item, budget) for key, item in value.items()}
    raise Unsendable(f"returned a {type(value).__name__}, which is no number, "
                     "array, tuple or dict")


def described(error, file):
    """An exception in words, with the line of the student's file it came from."""
    line = getattr(error, "lineno", None) if isinstance(error, SyntaxError) else None
    for frame in traceback.extract_tb(error.__traceback__):
        if frame.filename == file:
            line = frame.lineno
    text = (error.msg if isinstance(error, SyntaxError) else str(error))[:300]
    where = f" (line {line})" if line is not None else ""
    return f"{type(error).__name__}: {text}{where}" if text else \
        f"{type(error).__name__}{where}"


def main():
    setup = json.loads(sys.stdin.readline())
    source, file = setup["source"], setup["file"]
    # The names of the values of the functions that return several.
    fields = {function["name"]: [output["name"] for output in function["outputs"]]
              for function in setup["functions"] if len(function["outputs"]) > 1}
    reply({"ready": True})
    functions = {}
    for line in sys.stdin:
        if not line.strip():
            continue
        request = json.loads(line)
        if "load" in request:
            namespace = {"__name__": "__main__", "__file__": file}
            try:
                exec(compile(source, file, "exec"), namespace)
            except BaseException as error:
                reply({"error": described(error, file)})
                continue
            functions = {name: value for name, value in namespace.items()
                         if callable(value) and not name.startswith("_")}
            reply({"defined": sorted(functions)})
            continue
        name = request["call"]
        args = [argument(item["value"]) for item in request["args"]]
        try:
            result = functions[name](*args)
        except BaseException as error:
            reply({"error": described(error, file)})
            continue
        named = fields.get(name)
        if named and isinstance(result, tuple):
            if len(result) != len(named):
                reply({"error": f"returned a tuple of {len(result)} values, where "
                       f"{name} returns {len(named)}: {', '.join(named)}"})
                continue
            result = dict(zip(named, result))
        try:
            reply({"output": output(result, [MAX_VALUES])})
        except (Unsendable, RecursionError) as error:
            reply({"error": str(error) if isinstance(error, Unsendable)
                   else "returned a value nested too deeply"})


main()
