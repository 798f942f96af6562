// JavaScript on V8: a student's file and the harness every engine runs
// (`static/src/harness.js`, with the exercises' loops) in Node, inside the jail of
// `jail.rs`: a run in a process of its own, function phases one after another, each in
// a fresh realm. This file is a function of the harness's text, the loops' (name and
// text each) and the progress descriptor's number, which the server calls with them (see
// `NODE_PROGRAM` in `mod.rs`). It speaks one line of JSON at a time on stdin and stdout:
//
//   {"source": ..., "file": ...}            -> {"ready": "true"}
//   {"kind": "function"|"run", "phase": ...} -> {"report": the harness's report}
//
// and before each call of the student's functions writes where it is (the harness's
// label) over the start of the progress descriptor, ended by a zero byte: the server
// reads it if it stops the phase.
//
// Before the harness loads, a realm's global object is cut down to ECMAScript's
// built-ins, as QuickJS's is: no `require`, `process`, `console`, timers or WebAssembly,
// so that a file means the same on both engines. What this file needs of Node it has
// taken first, in its own scope, out of the student's reach. A run, its process's only
// phase, runs in Node's main realm: in a `vm` context every global the student's code
// reads, `Math` among them, goes through Node's interceptors, and a whole data set's run
// took half as long again. A function's tests are short, and each phase gets a fresh
// context, so that phases may share a process. The jail is the boundary: the server
// trusts nothing here beyond what the report says of the student's own outputs, which the
// grader checks. Time and memory are the server's to measure: the process's CPU time,
// all of its threads', and V8's heap limit.
(function (harnessText, loops, progressFd) {
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

  const label = Buffer.alloc(4096);
  /// Says where the harness is: `text` (cut to what the descriptor holds), then a zero.
  function progress(text) {
    const length = label.write(text, 0, label.length - 1, 'utf8');
    label[length] = 0;
    writeSync(progressFd, label, 0, length + 1, 0);
  }

  /// Writes a line `{"NAME": text}`, `text` a string: made here rather than by
  /// stringifying an object, so that no `toJSON` of the student's on Object.prototype is
  /// called.
  function say(name, text) {
    const bytes = encode('{"' + name + '":' + stringify(text) + '}\n');
    let written = 0;
    while (written < bytes.length) written += writeSync(1, bytes, written);
  }

  // ECMAScript's built-ins: what a fresh context has, but for the console and
  // WebAssembly that V8 and Node add to it.
  const builtIns = new Set(
    Object.getOwnPropertyNames(vm.runInContext('globalThis', vm.createContext())),
  );
  builtIns.delete('console');
  builtIns.delete('WebAssembly');
  /// A realm's global object cut down to ECMAScript's built-ins.
  function cut(global) {
    for (const name of Object.getOwnPropertyNames(global)) {
      if (!builtIns.has(name)) delete global[name];
    }
  }

  // V8's Function constructor says no line of a syntax error; compiling the same
  // arguments as a function of Node's does (its error's stack starts "student:LINE").
  const compileFunction = vm.compileFunction;
  const atLine = /^student:(\d+)\n/;
  const exec = RegExp.prototype.exec;
  function locate(params) {
    const names = [];
    for (let i = 0; i < params.length - 1; i++) names[i] = params[i];
    try {
      compileFunction(params[params.length - 1], names, { filename: 'student' });
      return null;
    } catch (error) {
      const found = Reflect.apply(exec, atLine, [String(error.stack)]);
      return found === null ? null : Number(found[1]);
    }
  }

  /// The harness and the loops loaded into a realm (`run(text, options)` evaluates in
  /// it), before any student code runs there.
  function harnessIn(run) {
    run(harnessText, { filename: 'harness.js' });
    for (const [name, text] of loops) run(text, { filename: name });
    return run('estlabHarness', {});
  }

  /// A fresh realm of its own for a function's tests: nothing the student's code did in
  /// an earlier one reaches it, as nothing reaches a phase in a process of its own. The
  /// object Node makes the context's global of has no prototype: an ordinary one's would
  /// be this realm's Object.prototype, whose `constructor.constructor` (reached as
  /// `globalThis.constructor.constructor`) is this realm's Function. Promise jobs the
  /// student's code leaves are the context's own and go with it.
  function freshRealm() {
    const context = vm.createContext(Object.create(null), { microtaskMode: 'afterEvaluate' });
    cut(vm.runInContext('globalThis', context));
    return harnessIn((text, options) => vm.runInContext(text, context, options));
  }

  cut(globalThis);

  const { source } = parse(line());
  // The progress descriptor is there before the harness says it is ready: a jail without
  // it is the sandbox's failure, not a phase's.
  fs.fstatSync(progressFd);
  say('ready', 'true');

  for (;;) {
    const request = parse(line());
    if (request.kind === 'run') {
      // A run, the process's only phase, in the main realm (see the top).
      const harness = harnessIn(runHere);
      harness.defineSyntaxLocator(locate);
      say('report', harness.run(source, request.phase, progress));
      return;
    }
    const harness = freshRealm();
    harness.defineSyntaxLocator(locate);
    say('report', harness.callFunction(source, request.phase, progress));
  }
})
