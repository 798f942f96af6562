// The student's functions in another language, as the harness in JavaScript calls them:
// the stand-ins the server writes for them (see `bridge.rs`) call `estlabNative`, which
// asks the student's interpreter, in its jail, through the host's two functions. No
// student code runs in this engine, so nothing here needs guarding against it; what comes
// back is the student's, and the harness checks it as it checks a JavaScript function's.
(function (global, hostLoad, hostCall) {
  'use strict';
  const parse = JSON.parse;
  const stringify = JSON.stringify;
  const slice = Array.prototype.slice;

  /// What the interpreter said went wrong, thrown as the harness describes an error:
  /// "ValueError: ... (line 12)" as the name ValueError and the rest.
  function fault(text) {
    const colon = text.indexOf(': ');
    const named = colon > 0 && /^[A-Za-z_][\w.]*$/.test(text.slice(0, colon));
    return named
      ? { name: text.slice(0, colon), message: text.slice(colon + 2) }
      : { name: 'Error', message: text };
  }

  /// Numbers JSON has none for, as the strings the grader uses for them.
  function encode(key, value) {
    return typeof value === 'number' && !Number.isFinite(value) ? String(value) : value;
  }

  /// The interpreter's answer, of the kind asked for (`defined` or `output`). Only the
  /// student's code, writing to the harness's own descriptor, makes it another.
  function answer(text, kind) {
    const reply = parse(text);
    if (typeof reply.error === 'string') throw fault(reply.error);
    if (reply === null || typeof reply !== 'object' || !(kind in reply)) {
      throw fault('your code wrote to the channel of the harness, out of turn');
    }
    return reply[kind];
  }

  global.estlabNative = Object.freeze({
    /// The file evaluated afresh in the interpreter: which functions it defines.
    load: function () {
      const defined = Object.create(null);
      const names = answer(hostLoad(), 'defined');
      for (let i = 0; i < names.length; i++) defined[names[i]] = true;
      return defined;
    },
    call: function (name, args) {
      return answer(hostCall(name, stringify(slice.call(args), encode)), 'output');
    },
  });
})(globalThis, estlabNativeLoad, estlabNativeCall);
