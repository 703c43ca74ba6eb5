#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| stridekit_fuzz_harness::run("packed_navigator_events", data));
