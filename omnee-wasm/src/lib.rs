//! wasm-bindgen bindings of omnee-core (filled in by its own issue).
#![forbid(unsafe_code)]
