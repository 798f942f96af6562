// Runs a student's file phase by phase on the server (`POST /api/phases`), for a language
// the browser cannot run (Python): the server carries out the phase in its sandbox, as a
// grading does, and answers the harness's output, which this page then grades and draws
// exactly as it does the outputs of its own Web Worker (runner.js). A refusal or a fault
// of the server's becomes the phase's error, said as the server said it.

/** @typedef {import('../types/Language').Language} Language */

export class ServerRunner {
  /**
   * @param {{ lab: string, language: () => Language, seed: () => number }} parts The
   *   exercise, and the file's language and the variant's seed at each phase.
   */
  constructor({ lab, language, seed }) {
    this.lab = lab;
    this.language = language;
    this.seed = seed;
    /** @type {AbortController | null} */
    this.running = null;
  }

  /** Stops waiting for the phase that is running, which then reports that it was stopped. */
  cancel() {
    this.running?.abort();
  }

  /**
   * Runs one phase of the job on the server: as `Runner.phase` does in the browser.
   *
   * @param {'function' | 'run'} kind
   * @param {string} source
   * @param {import('../types/FunctionPhase').FunctionPhase | import('../types/RunPhase').RunPhase} phase
   * @param {(during: string) => void} [onProgress]
   * @returns {Promise<any>} a FunctionOutput for a function's phase, a RunOutput for a run's
   */
  async phase(kind, source, phase, onProgress = () => {}) {
    const name = 'function' in phase ? phase.function : phase.name;
    const id = kind === 'function' ? { function: name } : { name };
    onProgress('on the server');
    const running = new AbortController();
    this.running = running;
    try {
      const response = await fetch('/api/phases', {
        method: 'POST',
        headers: { 'content-type': 'application/json' },
        body: JSON.stringify({ lab: this.lab, language: this.language(), seed: this.seed(), phase: name, source }),
        signal: running.signal,
      });
      /** @type {Partial<import('../types/Outputs').Outputs> & { error?: string }} */
      const answer = await response.json().catch(() => ({}));
      if (!response.ok) {
        return { ...id, error: `The server did not run it: ${answer.error ?? `${response.status} ${response.statusText}`}` };
      }
      const output = kind === 'function' ? answer.functions?.[0] : answer.runs?.[0];
      return output ?? { ...id, error: 'The server answered without the output of this phase.' };
    } catch (error) {
      if (running.signal.aborted) return { ...id, stopped: { during: name, cause: 'you stopped it' } };
      return { ...id, error: `The server could not be reached (${error.message}): try again.` };
    } finally {
      this.running = null;
    }
  }
}
