#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| luz::fuzzing::gltf(data));
