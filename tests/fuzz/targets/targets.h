// The fuzz targets: one function per reader of untrusted input, each taking one input's bytes
// through the same library calls as the `sdv` command that reads such a file (tests/fuzz/README.md).
// Each returns 0; a crash, a sanitizer report, an exception escaping a library that promises
// never to throw, or a broken property (sdv::fuzz::fail) is a finding. The same functions back
// the libFuzzer executables (fuzz_main.cpp) and the replay of the regressions in every build.
#pragma once

#include <cstddef>
#include <cstdint>

int sdv_fuzz_sdv_frontend(const uint8_t* data, size_t size);   // .sdv: lint, compile, fmt
int sdv_fuzz_ir_reader(const uint8_t* data, size_t size);      // .sdvir: check-ir, run
int sdv_fuzz_btree(const uint8_t* data, size_t size);          // .btree: lint, convert
int sdv_fuzz_gss_scenario(const uint8_t* data, size_t size);   // .gs.osm: lint, convert
int sdv_fuzz_lanelet2(const uint8_t* data, size_t size);       // Lanelet2 map of a run
int sdv_fuzz_cosim_frame(const uint8_t* data, size_t size);    // co-simulation frames, records
int sdv_fuzz_sweep_results(const uint8_t* data, size_t size);  // sweep directory: view, --report
int sdv_fuzz_recording(const uint8_t* data, size_t size);      // recorded traffic: replay, calibrate
int sdv_fuzz_run_dir(const uint8_t* data, size_t size);        // run directory: view, plot
int sdv_fuzz_run_diff(const uint8_t* data, size_t size);       // two run directories: diff --runs
int sdv_fuzz_sweep_rows(const uint8_t* data, size_t size);     // a sweep's rows: --resume, merge
