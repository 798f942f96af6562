// JavaScript on V8: a student's file and the harness every engine runs
// (`static/src/harness.js`, with the exercises' loops) in Node, one phase a process,
// inside the jail of `jail.rs`. This file is a function of the harness's text and the
// loops' (name and text each), which the server calls with them (see `NODE_PROGRAM` in
// `mod.rs`). It speaks one line of JSON at a time on stdin and stdout:
//
//   {"source": ..., "file": ...}            -> {"ready": "true"}, the harness loaded
//   {"kind": "function"|"run", "phase": ...} -> {"at": label} before each call of the
//                                              student's functions, then
//                                              {"report": the harness's report}
//
// Before the harness loads, the global object is cut down to ECMAScript's built-ins, as
// QuickJS's is: no `require`, `process`, `console`, timers or WebAssembly, so that a file
// means the same on both engines. What this file needs of Node it has taken first, in
// its own scope, out of the student's reach. (A `vm` context would keep Node's realm
// apart, but every global the student's code reads, `Math` among them, would then go
// through Node's interceptors: a whole data set's run took half as long again.) The jail
// is the boundary: the server trusts nothing here beyond what the report says of the
// student's own outputs, which the grader checks. Time and memory are the server's to
// measure: the process's CPU time, all of its threads', and V8's heap limit.
(function (harnessText, loops) {
  'use strict';
  const fs = require('node:fs');
  const vm = require('node:vm');
  const { readSync, writeSync } = fs;
  const runHere = vm.runInThisContext;
  const stringify = JSON.stringify;
  const parse = JSON.parse;
  const encode = Buffer.from.bind(Buffer);
  const chunk = Buffer.alloc(1 << 16);

  let pending = '';
  /// The next line of stdin that is not blank (read before any of the student's code
  /// runs: the setup and the one request).
  function line() {
    for (;;) {
      const end = pending.indexOf('\n');
      if (end >= 0) {
        const text = pending.slice(0, end);
        pending = pending.slice(end + 1);
        if (text.trim() !== '') return text;
        continue;
      }
      const n = readSync(0, chunk, 0, chunk.length, null);
      if (n === 0) throw new Error('the server closed the harness\'s input');
      pending += chunk.toString('utf8', 0, n);
    }
  }

  /// Writes a line `{"NAME": text}`, `text` a string: made here rather than by
  /// stringifying an object, so that no `toJSON` of the student's on Object.prototype is
  /// called.
  function say(name, text) {
    const bytes = encode('{"' + name + '":' + stringify(text) + '}\n');
    let written = 0;
    while (written < bytes.length) written += writeSync(1, bytes, written);
  }

  const builtIns = new Set(
    Object.getOwnPropertyNames(vm.runInContext('globalThis', vm.createContext())),
  );
  builtIns.delete('console');
  builtIns.delete('WebAssembly');
  for (const name of Object.getOwnPropertyNames(globalThis)) {
    if (!builtIns.has(name)) delete globalThis[name];
  }

  runHere(harnessText, { filename: 'harness.js' });
  for (const [name, text] of loops) runHere(text, { filename: name });
  const harness = globalThis.estlabHarness;
  // V8's Function constructor says no line of a syntax error; compiling the same
  // arguments as a function of Node's does (its error's stack starts "student:LINE").
  const compileFunction = vm.compileFunction;
  const atLine = /^student:(\d+)\n/;
  const exec = RegExp.prototype.exec;
  harness.defineSyntaxLocator((params) => {
    const names = [];
    for (let i = 0; i < params.length - 1; i++) names[i] = params[i];
    try {
      compileFunction(params[params.length - 1], names, { filename: 'student' });
      return null;
    } catch (error) {
      const found = Reflect.apply(exec, atLine, [String(error.stack)]);
      return found === null ? null : Number(found[1]);
    }
  });

  const { source } = parse(line());
  say('ready', 'true');

  const request = parse(line());
  // Where the harness is, told before each call of the student's functions: the server
  // names the last it heard when it stops the phase.
  const progress = (label) => say('at', label);
  const report = request.kind === 'run'
    ? harness.run(source, request.phase, progress)
    : harness.callFunction(source, request.phase, progress);
  say('report', report);
})
