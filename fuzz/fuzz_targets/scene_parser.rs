//! Arbitrary text into the CLI's TOML scene parser (`Scene::parse`): it must
//! return a scene or an error, never panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use omnee_cli::scene::Scene;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        let _ = Scene::parse(text);
    }
});
