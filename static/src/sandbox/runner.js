// Runs a student's code phase by phase, each phase in a Web Worker of its own (worker.js)
// under its time limit, as the server runs each phase in a fresh engine: nothing one phase
// leaves behind reaches another, and a worker that outlives its limit is terminated and
// the phase reports where it was stopped. The next worker starts while a phase runs.

/**
 * A worker that has said it is ready.
 *
 * @param {string} url
 * @returns {Promise<Worker>}
 */
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

/**
 * The harness's report as an object, or, when the student's code has spoiled it, the
 * phase failed with the reason (the server reads reports the same way).
 *
 * @param {{ function: string } | { name: string }} id
 * @param {string} text
 */
function readReport(id, text) {
  try {
    return JSON.parse(text);
  } catch (error) {
    return {
      ...id,
      error: "The test harness's report of this phase is unreadable, which happens when a " +
        `file changes built-in objects (${error.message}).`,
    };
  }
}

export class Runner {
  /** @param {string} url The worker's script. */
  constructor(url) {
    this.url = url;
    /** @type {Promise<Worker> | null} */
    this.spare = null;
    /** @type {((cause: string) => void) | null} */
    this.abort = null;
  }

  /** A fresh worker, and the next one starting. */
  take() {
    const worker = this.spare ?? startWorker(this.url);
    this.spare = startWorker(this.url);
    this.spare.catch(() => { this.spare = null; });
    return worker;
  }

  /** Stops the phase that is running, which then reports that it was stopped. */
  cancel() {
    this.abort?.('you stopped it');
  }

  /**
   * Runs one phase of the job: `kind` 'function' (phase = { function, calls, limit_ms })
   * or 'run' (phase = one data-set run). Resolves to the harness's output as an object:
   * a FunctionOutput or a RunOutput, with `stopped` set when the time limit ran out, the
   * worker died, or `cancel` was called.
   *
   * @param {'function' | 'run'} kind
   * @param {string} source
   * @param {import('../types/FunctionPhase').FunctionPhase | import('../types/RunPhase').RunPhase} phase
   * @param {(during: string) => void} [onProgress]
   * @returns {Promise<any>} a FunctionOutput for a function's phase, a RunOutput for a run's
   */
  async phase(kind, source, phase, onProgress = () => {}) {
    const worker = await this.take();
    const id = 'function' in phase ? { function: phase.function } : { name: phase.name };
    let during = 'your file';
    return new Promise((resolve) => {
      /** @type {ReturnType<typeof setTimeout> | undefined} */
      let timer;
      // The worker answers on a channel of this phase's own (see worker.js): messages the
      // student's code posts on the worker itself are never read.
      const channel = new MessageChannel();
      worker.onmessage = null;
      /** @param {object} output */
      const finish = (output) => {
        clearTimeout(timer);
        this.abort = null;
        channel.port1.close();
        worker.terminate();
        resolve(output);
      };
      /** @param {string} cause */
      const stopped = (cause) => finish({ ...id, stopped: { during, cause } });
      this.abort = stopped;
      timer = setTimeout(() => stopped('time'), phase.limit_ms);
      channel.port1.onmessage = ({ data }) => {
        if (data.progress !== undefined) {
          during = data.progress;
          onProgress(during);
        } else if (data.failure !== undefined) {
          finish({ ...id, error: `the test harness failed: ${data.failure}` });
        } else {
          finish(readReport(id, data.output));
        }
      };
      worker.onerror = (event) => {
        event.preventDefault();
        stopped(`the browser stopped the test worker (${event.message || 'out of memory?'})`);
      };
      worker.postMessage({ kind, source, phase, port: channel.port2 }, [channel.port2]);
    });
  }
}
