// The wasm build of the reference filters, loaded once per page.
import init, * as estlab from 'estlab-wasm/estlab_wasm.js';
import wasmUrl from 'estlab-wasm/estlab_wasm_bg.wasm';

let loading;

/** Resolves to the module's exports once the wasm module is compiled and instantiated. */
export function loadEstlab() {
  loading ??= init({ module_or_path: wasmUrl }).then(() => estlab);
  return loading;
}
