//! Arbitrary text into the CLI's TOML scene parser (`Scene::parse`): it must
//! return a scene or an error, never panic.
//!
//! omnee-cli is a binary crate without a library target, so its parser's
//! modules are compiled in here from their source files; they are private to
//! the binary otherwise.
#![no_main]
#![allow(dead_code, unused_imports)]

#[path = "../../omnee-cli/src/error.rs"]
mod error;
#[path = "../../omnee-cli/src/phase.rs"]
mod phase;
#[path = "../../omnee-cli/src/scene.rs"]
mod scene;

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        let _ = scene::Scene::parse(text);
    }
});
