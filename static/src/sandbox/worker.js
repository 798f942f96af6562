// The Web Worker that runs a student's code: the harness (the same file the server's
// sandbox runs) on one phase of a grading job. The page gives each phase a worker of its
// own and terminates it when the phase ends or outlives its time limit.
//
//   in:  { kind: 'function' | 'run', source, phase, port }   (phase: one entry of the job)
//   out, on `port` only: { progress: label } while it works, then { output } (JSON text)
//        or { failure }
//
// The page listens on the port it handed over, never on the worker itself, and the port
// is held here where the student's code cannot reach it, posted to with a postMessage
// captured before that code runs: a file cannot post a verdict of its own.
import '../harness.js';

const harness = self.estlabHarness;
const apply = Reflect.apply;
const postToPort = MessagePort.prototype.postMessage;
const errorMessage = (error) => String(error && error.message ? error.message : error);
const now = performance.now.bind(performance);
/// The harness says what it runs before every call of the student's code: the page hears
/// of it at most this often (in ms), enough to say where a phase ran out of time.
const PROGRESS_EVERY = 20;

self.onmessage = ({ data }) => {
  const { port } = data;
  const post = (message) => apply(postToPort, port, [message]);
  self.onmessage = null;
  const phase = JSON.stringify(data.phase);
  let told = -Infinity;
  const progress = (label) => {
    const time = now();
    if (time - told < PROGRESS_EVERY) return;
    told = time;
    post({ progress: String(label) });
  };
  try {
    const output = data.kind === 'function'
      ? harness.callFunction(data.source, phase, progress)
      : harness.run(data.source, phase, progress);
    post({ output });
  } catch (error) {
    // Only a fault of the harness itself gets here: it catches what student code throws.
    post({ failure: errorMessage(error) });
  }
};
self.postMessage({ ready: true });
