// Renames the module's imports and exports in wasm-bindgen's glue the way
// `wasm-opt --minify-imports-and-exports-and-modules` renamed them in the
// module (build.sh): the names wasm-bindgen gives them (`./omnee_wasm_bg.js`
// and `__wbg_error_6320ed1510f572e4` per import, `demo_lobeProbability` …)
// are 0.5 KiB of the module.
//
//   node minify.mjs MAP.json MODULE.wasm GLUE.js
//
// MAP.json is what wasm-opt printed: {"imports": [[module, name, new name]],
// "exports": [[name, new name]]}; MODULE.wasm the renamed module, which says
// the new module names. Fails (and writes nothing) unless every import is
// found in the glue and, afterwards, the glue provides every import of the
// module and uses no export the module lacks.
import { readFileSync, writeFileSync } from 'node:fs';

const [mapFile, wasmFile, glueFile] = process.argv.slice(2);
const map = JSON.parse(readFileSync(mapFile, 'utf8'));
const module = new WebAssembly.Module(readFileSync(wasmFile));
let glue = readFileSync(glueFile, 'utf8');

const escape = (s) => s.replace(/[.*+?^${}()|[\]\\]/g, '\\$&');
// Replaces every match of `pattern`, which must occur unless `optional`.
const rename = (pattern, to, what, optional = false) => {
  const re = new RegExp(pattern, 'g');
  if (!optional && !re.test(glue)) throw new Error(`minify.mjs: ${what} not found in ${glueFile}`);
  glue = glue.replace(re, to);
};

// Exports: `wasm.name` (a whole word); the glue uses some only.
for (const [from, to] of map.exports) {
  rename(`\\bwasm\\.${escape(from)}\\b`, `wasm.${to}`, `export ${from}`, true);
}
// Imports: the keys of the import objects, `name: function`, and the
// modules' keys, `"module": importN`.
const newModule = new Map(WebAssembly.Module.imports(module).map((i) => [i.name, i.module]));
const modules = new Map();
for (const [mod, from, to] of map.imports) {
  rename(`\\b${escape(from)}(?=: function)`, to, `import ${from}`);
  modules.set(mod, newModule.get(to));
}
for (const [from, to] of modules) {
  if (to === undefined) throw new Error(`minify.mjs: no module for ${from} in ${wasmFile}`);
  rename(`"${escape(from)}"(?=: import)`, `"${to}"`, `import module ${from}`);
}

// Every import the module has is a key of the glue's, every export it uses
// is the module's.
for (const { module: mod, name } of WebAssembly.Module.imports(module)) {
  if (!glue.includes(`"${mod}": import`) || !new RegExp(`\\b${escape(name)}: function`).test(glue)) {
    throw new Error(`minify.mjs: the glue does not provide ${mod}.${name}`);
  }
}
const exported = new Set(WebAssembly.Module.exports(module).map((e) => e.name));
for (const [, name] of glue.matchAll(/\bwasm\.([A-Za-z_$][\w$]*)/g)) {
  if (!exported.has(name)) throw new Error(`minify.mjs: the glue uses wasm.${name}, not exported`);
}
writeFileSync(glueFile, glue);
