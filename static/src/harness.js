// The harness that calls a student's code: this one file runs unchanged in the browser's
// Web Worker and in the server's QuickJS sandbox. It takes a phase of a grading job (made
// by `labs::grading::Plan::job`) as JSON, calls the student's functions on copies of the
// inputs, and returns JSON that `labs::grading::Plan::grade` compares with the reference:
//
//   estlabHarness.callFunction(source, phaseJson, progress[, declaring])
//                                                           -> outputs of one function
//   estlabHarness.run(source, runJson, progress)             -> one run of the exercise's
//                                                              loop (a data set, a path)
//
// `progress(label)` is told what is about to run, so that the host can say where its time
// limit stopped the code. `declaring` says how a missing function is declared in the
// student's language (`def NAME(...):`; JavaScript's when not given): the server passes
// a file in another language as stand-ins of its functions (`server/src/sandbox/native`). Numbers JSON cannot hold are written "NaN", "Infinity" and
// "-Infinity", undefined as "undefined".
//
// The student's code runs in this realm, so the harness's bookkeeping is built to be out
// of its reach (DESIGN.md, "Grading that cannot be gamed"): every built-in the harness
// uses is captured before the file is evaluated; every record is an own data property
// defined with `put` (never an assignment, which a setter on Object.prototype or
// Array.prototype could swallow) on an object the harness made; the harness reads only
// own properties of its own objects; and the report is JSON text written here. What the
// harness cannot stop, the grader catches: it fails closed (a case without a result has
// failed, an unreadable report fails its phase).
(function (global) {
  'use strict';

  // Built-ins captured before any student code runs: a file that replaces JSON.stringify
  // or Array.prototype.push changes nothing in here (the harness calls no array methods).
  const FunctionConstructor = Function;
  const ErrorConstructor = Error;
  const ProxyConstructor = Proxy;
  const apply = Reflect.apply;
  const isArray = Array.isArray;
  const keysOf = Object.keys;
  const freeze = Object.freeze;
  const defineProperty = Object.defineProperty;
  const createObject = Object.create;
  const setPrototypeOf = Object.setPrototypeOf;
  const ArrayPrototype = Array.prototype;
  const isView = ArrayBuffer.isView;
  const hasOwn = Object.hasOwn;
  const stringify = JSON.stringify;
  const parse = JSON.parse;
  const numberIsFinite = Number.isFinite;
  const toText = String;
  const stringSlice = String.prototype.slice;
  const stringReplace = String.prototype.replace;
  const charCodeAt = String.prototype.charCodeAt;
  const regExpExec = RegExp.prototype.exec;
  const weakSetAdd = WeakSet.prototype.add;
  const weakSetHas = WeakSet.prototype.has;

  /// Values the student's code may return from one call, at most: the largest answer of
  /// any contract is the EKF exercise's associate with 40 landmarks, 482 values. More is not an answer, and
  /// would only make the reports (and the host's memory) large. Strings and field names
  /// count their characters against a budget of their own.
  const MAX_VALUES = 2000;
  const MAX_TEXT = 4000;
  const MAX_DEPTH = 8;

  // Names a student's file may reach for that the sandbox does not give it: each is
  // shadowed by a stand-in that says so when used.
  const UNAVAILABLE = ['require', 'process', 'fetch', 'XMLHttpRequest', 'WebSocket',
    'importScripts', 'postMessage', 'close', 'Deno', 'Bun'];
  // What `import(...)` calls become (see load).
  const IMPORT_STAND_IN = 'estlabImportIsNotAvailable';
  // What the end of the student's file calls with its functions (see load).
  const TAKE = 'estlabTakeFunctions';
  const WHY = ' is not available here: your file runs on its own, with no modules, ' +
    'files or network. Write everything it needs in the file itself.';

  function unavailable(name) {
    const fail = function () { throw new ErrorConstructor(name + WHY); };
    return new ProxyConstructor(fail, {
      get: fail, set: fail, apply: fail, construct: fail, has: fail,
    });
  }
  /// Records `value` as the own data property `key` of `target`, whatever accessors the
  /// student's code put on the prototypes.
  function put(target, key, value) {
    defineProperty(target, key, { value, writable: true, enumerable: true, configurable: true });
    return value;
  }
  function push(list, value) {
    put(list, list.length, value);
  }
  /// An object of the harness's own, with no prototype to tamper with.
  function record() {
    return createObject(null);
  }
  /// An array to fill by assignment while it has no prototype, so that no setter of the
  /// student's on Array.prototype or Object.prototype is met, then made ordinary
  /// (`guarded`): as safe as `put` item by item, and many times faster on V8, where
  /// defining each index takes the slow path (a whole data set's run copies millions of
  /// values).
  function unguarded() {
    return setPrototypeOf([], null);
  }
  function guarded(array) {
    return setPrototypeOf(array, ArrayPrototype);
  }

  // Stack traces as call sites (Error.prepareStackTrace, in V8 and QuickJS) would hand
  // the student's code the harness's own functions: the hook is fixed to nothing.
  try {
    defineProperty(ErrorConstructor, 'prepareStackTrace',
      { value: undefined, writable: false, configurable: false });
  } catch {
    // Already fixed in place by the engine: there is no hook to take away.
  }

  const standIns = [];
  for (let i = 0; i < UNAVAILABLE.length; i++) push(standIns, unavailable(UNAVAILABLE[i]));
  push(standIns, unavailable('import(...)'));

  // The line of the student's file that an error's stack names: the first frame in code
  // made by the Function constructor (V8 "<anonymous>:5:15", QuickJS "<input>:5:15",
  // Firefox "> Function:5:15"; a syntax error in Node "<anonymous_script>:5"),
  // calibrated once, since every engine wraps a Function body in a header of its own
  // length.
  const LINE = /(?:<anonymous(?:_script)?>|<input>|> Function):(\d+)/;
  function stackLine(stack) {
    const found = typeof stack === 'string' ? apply(regExpExec, LINE, [stack]) : null;
    return found ? +found[1] : null;
  }
  let lineOffset = null;
  try {
    FunctionConstructor('throw new Error("probe");')();
  } catch (probe) {
    const line = stackLine(probe.stack);
    lineOffset = line === null ? null : line - 1;
  }

  /// What was thrown, in words. The thrown value is the student's: its getters and a
  /// Proxy's traps may throw in turn, which is said rather than passed on.
  function describeError(error) {
    try {
      return describeThrown(error);
    } catch {
      return 'a value that cannot be described (reading it threw)';
    }
  }

  /// Each property is read once, and only a string is taken for a text: a getter may
  /// answer differently when read again, and an object's `length` need not be its text's
  /// (a name that is short when checked and a megabyte when used). No `instanceof`: it
  /// would run a Proxy's getPrototypeOf trap. (A `null` thrown is what QuickJS throws when
  /// it has no memory even for the error; the host tells that from the engine's state.)
  function describeThrown(error) {
    if (error === null || (typeof error !== 'object' && typeof error !== 'function')) {
      return 'a value that is not an Error: ' + clip(safeText(error));
    }
    const message = error.message;
    if (typeof message !== 'string') {
      return 'a value that is not an Error: ' + clip(safeText(error));
    }
    const name = error.name;
    const line = stackLine(error.stack);
    const where = line !== null && lineOffset !== null && line > lineOffset
      ? ' (line ' + (line - lineOffset) + ')' : '';
    return (typeof name === 'string' ? clip(name, NAME_LENGTH) : 'Error') + ': ' +
      clip(message) + where;
  }

  function safeText(value) {
    try { return toJson(plain(value)); } catch { return typeof value; }
  }

  /// Characters kept of a text the student's code made (a message, a string it returned).
  const TEXT_LENGTH = 300;
  /// Characters kept of a name it made (an error's name, a field of a returned object).
  const NAME_LENGTH = 60;

  /// A string the student's code made, at most `length` characters, cut between code
  /// points and with every lone half of a surrogate pair (which JSON text cannot carry to
  /// the host) made U+FFFD: the report must read, whatever the text.
  function clip(text, length = TEXT_LENGTH) {
    let kept = text;
    if (text.length > length) {
      // Cutting after a pair's first half would leave that half alone.
      const first = apply(charCodeAt, text, [length - 1]);
      const end = first >= 0xd800 && first <= 0xdbff ? length - 1 : length;
      kept = apply(stringSlice, text, [0, end]) + '...';
    }
    return apply(stringReplace, kept, [SURROGATES, wellFormed]);
  }

  /// A surrogate pair, or a half of one alone.
  const SURROGATES = /[\ud800-\udbff][\udc00-\udfff]|[\ud800-\udfff]/g;
  function wellFormed(found) {
    return found.length === 2 ? found : '\ufffd';
  }

  /// JSON text of plain data, written here rather than by JSON.stringify, which a file
  /// could redirect with a toJSON method on Object.prototype.
  function toJson(value) {
    if (value === null) return 'null';
    switch (typeof value) {
      case 'number':
        return numberIsFinite(value) ? toText(value) : stringify(toText(value));
      case 'boolean':
        return toText(value);
      case 'undefined':
        return '"undefined"';
      case 'string':
        return stringify(value);
    }
    let text;
    if (isArray(value)) {
      text = '[';
      for (let i = 0; i < value.length; i++) text += (i ? ',' : '') + toJson(value[i]);
      return text + ']';
    }
    const names = keysOf(value);
    text = '{';
    for (let i = 0; i < names.length; i++) {
      text += (i ? ',' : '') + stringify(names[i]) + ':' + toJson(value[names[i]]);
    }
    return text + '}';
  }

  // There are no modules here, and the engines' own messages for `import` and `export`
  // lines do not say so: such a line stops the file with a message that does. An
  // `import(...)` call becomes a call of a stand-in that says so when it runs.
  const MODULE_LINE = /^[ \t]*(?:import|export)\b/m;
  const DYNAMIC_IMPORT = /(^|[^\w$.])import(\s*\()/g;
  const NO_MODULES = 'There are no modules here: declare the functions at top level, ' +
    'without import or export, and write everything the file needs in the file itself.';

  function moduleLine(source) {
    const found = apply(regExpExec, MODULE_LINE, [source]);
    if (!found) return null;
    let line = 1;
    for (let i = 0; i < found.index; i++) if (source[i] === '\n') line++;
    return line;
  }

  /// The parameters and body of the function that evaluates the student's file and
  /// returns its top-level functions of these `names` (the phase's, from the job), made
  /// before any of the student's code runs (see load).
  function prepare(source, names) {
    const line = moduleLine(source);
    if (line !== null) {
      throw new HarnessError('Your file does not compile: an import or export (line ' + line +
        '). ' + NO_MODULES);
    }
    let body = apply(stringReplace, source, [DYNAMIC_IMPORT, '$1' + IMPORT_STAND_IN + '$2']) +
      '\n;' + TAKE + '(';
    for (let i = 0; i < names.length; i++) {
      const name = names[i];
      if (apply(regExpExec, IDENTIFIER, [name]) === null) {
        throw new HarnessError('the job names a function that is no identifier');
      }
      body += 'typeof ' + name + " === 'function' ? " + name + ' : undefined,';
    }
    body += ');';
    const params = [];
    for (let i = 0; i < UNAVAILABLE.length; i++) push(params, UNAVAILABLE[i]);
    push(params, IMPORT_STAND_IN);
    push(params, TAKE);
    push(params, body);
    const prepared = record();
    put(prepared, 'names', names);
    put(prepared, 'params', params);
    return prepared;
  }

  /// A name the harness may write into the body of `prepare`.
  const IDENTIFIER = /^[A-Za-z_][A-Za-z0-9_]*$/;

  /// The student's file (prepared) evaluated afresh: its top-level functions of the
  /// phase, in a record of the harness's. The end of the file hands them to a function
  /// of the harness's rather than returning them: what the file's code returns (a
  /// `return` at its top level) is never read, and one that returns early is told so.
  function load(prepared) {
    let make;
    try {
      make = apply(FunctionConstructor, undefined, prepared.params);
    } catch (error) {
      throw new HarnessError('Your file does not compile: ' + describeError(error) +
        syntaxErrorLine(error, prepared.params));
    }
    const names = prepared.names;
    let functions = null;
    const take = function () {
      functions = record();
      for (let i = 0; i < names.length; i++) put(functions, names[i], arguments[i]);
    };
    const args = [];
    for (let i = 0; i < standIns.length; i++) push(args, standIns[i]);
    push(args, take);
    try {
      apply(make, undefined, args);
    } catch (error) {
      throw new HarnessError('Your file throws while it loads: ' + describeError(error));
    }
    if (functions === null) {
      throw new HarnessError('Your file returns at its top level: a return statement ' +
        'outside any function ends the file before its functions can be taken. Remove it.');
    }
    return functions;
  }

  /// The harness's own errors, told from the student's by identity (a WeakSet runs no
  /// trap of a Proxy, as instanceof would).
  const harnessErrors = new WeakSet();
  function HarnessError(message) {
    put(this, 'message', message);
    apply(weakSetAdd, harnessErrors, [this]);
  }
  function isHarnessError(error) {
    return apply(weakSetHas, harnessErrors, [error]);
  }

  /// How JSON carries the numbers it has none for, both ways (`labs::grading::infinity`).
  const INFINITY = 'Infinity';
  const MINUS_INFINITY = '-Infinity';
  const NOT_A_NUMBER = 'NaN';

  /// A deep copy of JSON data from the job, with "Infinity" back as a number: every call
  /// gets inputs of its own, so a function that changes its arguments harms nothing.
  function copy(value) {
    if (value === INFINITY) return Infinity;
    if (!isArray(value)) return value;
    const n = value.length;
    const out = unguarded();
    for (let i = 0; i < n; i++) out[i] = copy(value[i]);
    return guarded(out);
  }

  const PROMISE = 'returned a Promise: return the result itself, not async';

  /// What the student's code returned, as JSON data (see the top of the file).
  function plain(value) {
    const budget = { left: MAX_VALUES, text: MAX_TEXT };
    return walk(value, 0, budget);
  }

  /// A text of the returned value, charged to the budget.
  function text(value, budget) {
    budget.text -= value.length;
    if (budget.text < 0) {
      throw new HarnessError('returned more than ' + MAX_TEXT + ' characters of text');
    }
    return value;
  }

  /**
   * @param {any} value Whatever the student's code returned.
   * @param {number} depth
   * @param {{ left: number }} budget
   */
  function walk(value, depth, budget) {
    if (--budget.left < 0) {
      throw new HarnessError('returned more than ' + MAX_VALUES + ' values');
    }
    switch (typeof value) {
      case 'number':
        if (numberIsFinite(value)) return value;
        return value !== value ? NOT_A_NUMBER : value > 0 ? INFINITY : MINUS_INFINITY;
      case 'boolean':
        return value;
      case 'undefined':
        return 'undefined';
      case 'string':
        return text(clip(value), budget);
      case 'bigint':
        return toText(value) + 'n';
      case 'function':
        return 'a function';
      case 'symbol':
        return 'a symbol';
    }
    if (value === null) return null;
    if (depth >= MAX_DEPTH) throw new HarnessError('returned data nested too deep');
    if (typeof value.then === 'function') throw new HarnessError(PROMISE);
    if (isArray(value) || isView(value)) {
      // A DataView has no length, and gives an empty array.
      const items = /** @type {ArrayLike<unknown>} */ (value);
      const n = items.length || 0;
      const out = unguarded();
      for (let i = 0; i < n; i++) out[i] = walk(items[i], depth + 1, budget);
      return guarded(out);
    }
    const object = record();
    const names = keysOf(value);
    for (let i = 0; i < names.length; i++) {
      const name = text(clip(names[i], NAME_LENGTH), budget);
      put(object, name, walk(value[names[i]], depth + 1, budget));
    }
    return object;
  }

  function callFunction(source, phaseJson, progress, declaring) {
    loopsOpen = false;
    const phase = parse(phaseJson);
    const out = record();
    put(out, 'function', phase.function);
    put(out, 'results', []);
    put(out, 'repeats', []);
    let functions;
    let prepared;
    try {
      prepared = prepare(source, [phase.function]);
      functions = load(prepared);
    } catch (error) {
      put(out, 'error', isHarnessError(error) ? error.message : describeError(error));
      return toJson(out);
    }
    const f = functions[phase.function];
    if (typeof f !== 'function') {
      const as = typeof declaring === 'string'
        ? apply(stringReplace, declaring, ['NAME', phase.function])
        : 'function ' + phase.function + '(...) { ... }';
      put(out, 'error', phase.function + ' is not defined: declare it at top level, as ' + as);
      return toJson(out);
    }
    const calls = phase.calls;
    for (let i = 0; i < calls.length; i++) {
      progress(calls[i].id);
      push(out.results, call(f, calls[i]));
    }
    // Every call once more, in reverse order, in a fresh copy of the file: a function
    // that keeps state between calls then answers some call differently.
    if (calls.length > 0) {
      let again;
      try {
        again = load(prepared)[phase.function];
      } catch (error) {
        put(out, 'error', isHarnessError(error) ? error.message : describeError(error));
        return toJson(out);
      }
      for (let i = calls.length - 1; i >= 0; i--) {
        progress(calls[i].id + ' (again, in a fresh copy of your file, in reverse order)');
        push(out.repeats, call(again, calls[i]));
      }
    }
    return toJson(out);
  }

  function call(f, testCall) {
    const result = record();
    put(result, 'id', testCall.id);
    try {
      put(result, 'output', plain(apply(f, undefined, copy(testCall.args))));
    } catch (error) {
      put(result, 'error',
        isHarnessError(error) ? error.message : 'threw ' + describeError(error));
    }
    return result;
  }

  // ---- the runs of an exercise's loop, with the student's functions ----

  /// One run of the loop named by the job (`run.loop`) over the run's data: the file is
  /// loaded, the functions the loop calls checked, and the loop records what it computes
  /// in the report's `record`. Whatever stops it is recorded with what was being done (`at.doing`).
  function run(source, runJson, progress) {
    loopsOpen = false;
    const job = parse(runJson);
    const out = record();
    put(out, 'name', job.name);
    const at = record();
    put(at, 'doing', 'loading your file');
    put(at, 'step', '');
    progress(job.name + ': ' + at.doing);
    try {
      const loop = hasOwn(LOOPS, job.loop) ? LOOPS[job.loop] : null;
      if (loop === null) throw new HarnessError('the job names no loop the harness has');
      const functions = load(prepare(source, job.functions));
      for (let i = 0; i < job.functions.length; i++) {
        if (typeof functions[job.functions[i]] !== 'function') {
          throw new HarnessError(job.functions[i] + ' is not defined');
        }
      }
      // Calls a student function by name, saying first (to the host too) where in the
      // loop it is: at the step `at.step` names, or as `label` says. `take` makes what it
      // returned the harness's own: all of it (`plain`), or the parts a loop reads of an
      // answer it reads little of (each part then goes through `plain`).
      const invoke = (name, args, label, take = plain) => {
        at.doing = label === undefined ? at.step + name : label;
        progress(job.name + ': ' + at.doing);
        const answer = apply(functions[name], undefined, args);
        if (take !== plain && answer !== null && typeof answer === 'object' &&
          typeof answer.then === 'function') {
          throw new HarnessError(PROMISE);
        }
        return take(answer);
      };
      // What the loop records (read as the exercise's record type in Rust).
      const kept = put(out, 'record', record());
      loop(job, kept, invoke, at);
    } catch (error) {
      put(out, 'error', (at.doing ? at.doing + ': ' : '') +
        (isHarnessError(error) ? error.message : 'threw ' + describeError(error)));
    }
    return toJson(out);
  }

  /// The record of an object's field the loop reads, checked.
  function field(object, name, check) {
    if (object === null || typeof object !== 'object' || !hasOwn(object, name)) {
      throw new HarnessError('returned ' + describe(object) + ' without the field ' + name);
    }
    return check(object[name], name);
  }

  /// Where a file that does not compile goes wrong, when the engine's error does not say
  /// (V8's Function constructor in Node): " (line N)" from the host's locator, which is
  /// given the Function constructor's arguments, or nothing.
  let locateSyntaxError = null;
  function syntaxErrorLine(error, params) {
    if (locateSyntaxError === null || stackLine(error.stack) !== null) return '';
    const line = locateSyntaxError(params);
    return typeof line === 'number' ? ' (line ' + line + ')' : '';
  }

  /// The host's locator of syntax errors, given before any phase.
  function defineSyntaxLocator(locate) {
    if (!loopsOpen || locateSyntaxError !== null) {
      throw new ErrorConstructor('the locator of syntax errors cannot be defined now');
    }
    locateSyntaxError = locate;
  }

  /// The loops of the exercises' runs, by the name their jobs give (`RunPhase` in Rust):
  /// each exercise's `web/loop.js` adds its own with `estlabHarness.defineLoop(name, make)`
  /// as the harness is loaded, before any student code runs; the first phase closes the
  /// list. `make(tools)` returns the loop, `loop(run, kept, invoke, at)`, which reads the
  /// run's data, calls the student's functions through `invoke` and records in `kept`.
  const LOOPS = createObject(null);
  let loopsOpen = true;
  function defineLoop(name, make) {
    if (!loopsOpen || hasOwn(LOOPS, name)) {
      throw new ErrorConstructor('the loop ' + name + ' cannot be defined now');
    }
    put(LOOPS, name, make(TOOLS));
  }

  // Checks of what the loop passes on: a precise message instead of NaN later on.
  function finiteNumber(value, what) {
    if (typeof value !== 'number' || !numberIsFinite(value)) {
      throw new HarnessError(what + ' is ' + describe(value) + ', not a finite number');
    }
    return value;
  }

  function flag(value, what) {
    if (typeof value !== 'boolean') {
      throw new HarnessError(what + ' is ' + describe(value) + ', not true or false');
    }
    return value;
  }

  function list(n) {
    return (value, what) => {
      if (!isArray(value) || value.length !== n) {
        throw new HarnessError(what + ' should be an array of ' + n + ' elements, but is ' +
          describe(value));
      }
      return value;
    };
  }

  function vector(n) {
    return (value, what) => {
      list(n)(value, what);
      for (let i = 0; i < n; i++) finiteNumber(value[i], what + '[' + i + ']');
      return value;
    };
  }

  function matrix(rows, cols) {
    return (value, what) => {
      list(rows)(value, what);
      for (let i = 0; i < rows; i++) vector(cols)(value[i], what + '[' + i + ']');
      return value;
    };
  }

  function threshold(value, what) {
    if (value === INFINITY) return Infinity;
    if (typeof value !== 'number' || !(value >= 0)) {
      throw new HarnessError(what + ' is ' + describe(value) + ', not a number >= 0');
    }
    return value;
  }

  function describe(value) {
    if (isArray(value)) {
      // Read again here (a loop may check a part of an answer it has not copied): only
      // a number is said.
      const length = value.length;
      return typeof length === 'number' ? 'an array of ' + length + ' elements' : 'an array';
    }
    if (value !== null && typeof value === 'object') {
      const names = keysOf(value);
      let fields = 'an object with the fields';
      for (let i = 0; i < names.length; i++) {
        fields += (i > 0 ? ', ' : ' ') + clip(names[i], NAME_LENGTH);
      }
      return clip(fields);
    }
    return clip(safeText(value));
  }

  /// What the harness gives the exercises' loops: its checks, and its ways of recording
  /// that the student's code cannot tamper with.
  const TOOLS = freeze({
    HarnessError, put, push, copy, plain, field, list, vector, matrix, threshold, describe,
    number: finiteNumber, flag,
  });

  global.estlabHarness = freeze({
    callFunction: callFunction, run: run, defineLoop: defineLoop,
    defineSyntaxLocator: defineSyntaxLocator,
  });
})(globalThis);
