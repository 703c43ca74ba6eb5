#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| stridekit_fuzz_harness::run("restore_map", data));
