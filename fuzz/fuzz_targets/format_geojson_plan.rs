#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| stridekit_fuzz_harness::run("format_geojson_plan", data));
