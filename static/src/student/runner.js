// Runs a student's code phase by phase in a Web Worker (worker.js), each phase under its
// time limit: a worker that outlives it is terminated, the phase reports where it was
// stopped, and the next phase gets a fresh worker.

/** A worker that has said it is ready. */
function startWorker(url) {
  return new Promise((resolve, reject) => {
    const worker = new Worker(url);
    worker.onmessage = ({ data }) => {
      if (data.ready) resolve(worker);
    };
    worker.onerror = (event) => {
      event.preventDefault();
      reject(new Error(`the test worker did not start: ${event.message ?? 'unknown error'}`));
    };
  });
}

export class Runner {
  /** `url`: the worker's script. */
  constructor(url) {
    this.url = url;
    this.worker = null;
    this.abort = null;
  }

  async ready() {
    this.worker ??= startWorker(this.url);
    return this.worker;
  }

  /** Stops the phase that is running, which then reports that it was stopped. */
  cancel() {
    this.abort?.('you stopped it');
  }

  /** Drops the current worker (stopping whatever it runs). */
  async stop() {
    const worker = this.worker;
    this.worker = null;
    if (worker) (await worker.catch(() => null))?.terminate();
  }

  /**
   * Runs one phase of the job: `kind` 'function' (phase = { function, calls, limit_ms })
   * or 'run' (phase = one data-set run). Resolves to the harness's output as an object:
   * a FunctionOutput or a RunOutput, with `stopped` set when the time limit ran out or
   * the worker died.
   */
  async phase(kind, source, phase, onProgress = () => {}) {
    const worker = await this.ready();
    const id = kind === 'function' ? { function: phase.function } : { name: phase.name };
    let during = 'your file';
    return new Promise((resolve) => {
      const stopped = (cause) => {
        clearTimeout(timer);
        this.abort = null;
        this.stop();
        resolve({ ...id, stopped: { during, cause } });
      };
      this.abort = stopped;
      const timer = setTimeout(() => stopped('time'), phase.limit_ms);
      worker.onmessage = ({ data }) => {
        if (data.progress !== undefined) {
          during = data.progress;
          onProgress(during);
          return;
        }
        clearTimeout(timer);
        this.abort = null;
        worker.onmessage = null;
        worker.onerror = null;
        if (data.failure !== undefined) resolve({ ...id, error: `the test harness failed: ${data.failure}` });
        else resolve(JSON.parse(data.output));
      };
      worker.onerror = (event) => {
        event.preventDefault();
        stopped(`the browser stopped the test worker (${event.message || 'out of memory?'})`);
      };
      worker.postMessage({ kind, source, phase });
    });
  }
}
