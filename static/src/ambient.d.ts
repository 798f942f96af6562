// What the scripts see that no file of src/ exports: the modules the asset build
// (build.mjs) makes up, and the global the test harness (harness.js) defines for the
// worker and the exercises' loops.

declare module '*.wasm' {
  /** The URL of the module, as esbuild's file loader gives it. */
  const url: string;
  export default url;
}

declare module 'estlab:workbenches' {
  /**
   * Each exercise's views of its runs (its folder's `web/workbench.js`), by folder: the
   * workbench's, and the report's where the exercise asks for a report.
   */
  const workbenches: Record<
    string,
    () => Promise<{
      runs: import('./workbench/running.js').ExerciseRuns<any>;
      report?: import('./report/runs.js').ReportRuns<any>;
    }>
  >;
  export default workbenches;
}

/** Reports what the harness is running, for the host to say where a phase stopped. */
type Progress = (label: string) => void;

/** A check of what the student's code returned: the value, or a `HarnessError` naming `what`. */
type Check<T> = (value: unknown, what: string) => T;

/** What the harness gives the exercises' loops (`TOOLS` in harness.js). */
interface LoopTools {
  HarnessError: new (message: string) => Error;
  put<T>(target: object, key: string | number, value: T): T;
  push<T>(list: T[], value: T): void;
  copy<T>(value: T): T;
  /** What the student's code returned, made the harness's own data (JSON's values). */
  plain(value: unknown): unknown;
  field<T>(object: unknown, name: string, check: Check<T>): T;
  list(n: number): Check<unknown[]>;
  vector(n: number): Check<number[]>;
  matrix(rows: number, cols: number): Check<number[][]>;
  threshold: Check<number>;
  number: Check<number>;
  flag: Check<boolean>;
  describe(value: unknown): string;
}

/**
 * An exercise's loop: reads the run's data (`Run`, with the `RunPhase` envelope), calls the
 * student's functions through `invoke`, and records in `kept` (`Kept`, the exercise's
 * record); `at` says what it is doing, for the messages.
 */
type Loop<Run, Kept> = (
  run: import('./types/RunPhase').RunPhase & Run,
  kept: Kept,
  invoke: <T = unknown>(
    name: string,
    args: unknown[],
    label?: string,
    take?: (answer: unknown) => T,
  ) => T,
  at: { doing: string; step: string },
) => void;

/** The test harness, as harness.js defines it. */
declare var estlabHarness: {
  callFunction(source: string, phaseJson: string, progress: Progress): string;
  run(source: string, runJson: string, progress: Progress): string;
  defineLoop<Run, Kept>(name: string, make: (tools: LoopTools) => Loop<Run, Kept>): void;
  /** The host's way to find the line of a syntax error (given the Function constructor's
   * arguments), where the engine's error does not say it. */
  defineSyntaxLocator(locate: (params: string[]) => number | null): void;
};

declare module 'markdown-it-texmath' {
  /** The plugin: `markdown.use(texmath, { engine, delimiters, katexOptions })`. */
  const texmath: import('markdown-it').PluginWithOptions<{
    engine: unknown;
    delimiters?: string | string[];
    katexOptions?: Record<string, unknown>;
  }>;
  export default texmath;
}
