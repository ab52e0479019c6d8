//! Arbitrary text into the library's TOML scene parser (`Scene::parse`,
//! slab and underwater scenes): it must return a scene or an error, never
//! panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use omnee_render::scenes::Scene;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        let _ = Scene::parse(text);
    }
});
