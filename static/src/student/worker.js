// The Web Worker that runs a student's code: the harness (the same file the server's
// sandbox runs) on one phase of a grading job. The page gives each phase a worker of its
// own and terminates it when the phase ends or outlives its time limit.
//
//   in:  { kind: 'function' | 'run', source, phase }   (phase: one entry of the job)
//   out: { progress: label } while it works, then { output } (JSON text) or { failure }
import '../harness.js';

const post = self.postMessage.bind(self);
const harness = self.estlabHarness;

self.onmessage = ({ data }) => {
  const phase = JSON.stringify(data.phase);
  const progress = (label) => post({ progress: String(label) });
  try {
    const output = data.kind === 'function'
      ? harness.callFunction(data.source, phase, progress)
      : harness.runFilter(data.source, phase, progress);
    post({ output });
  } catch (error) {
    // Only a fault of the harness itself gets here: it catches what student code throws.
    post({ failure: String(error && error.message ? error.message : error) });
  }
};
post({ ready: true });
