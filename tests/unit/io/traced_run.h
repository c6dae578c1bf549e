// A real run in the tests: a scenario written as text, run with its decision trace, its outputs
// written to a directory as `sdv run --trace -o DIR` writes them.
#pragma once

#include <doctest/doctest.h>

#include <string>

#include "runtime/io/outputs.h"
#include "runtime/io/recorder.h"
#include "runtime/sim/world.h"
#include "tests/unit/io/compile_text.h"

namespace sdv::test {

inline void write_traced_run(const std::string& scenario_text, const std::string& dir) {
    auto p = compile_text(scenario_text);
    REQUIRE(p);
    io::Recorder rec;
    sim::RunOptions options;
    options.trace = true;
    const auto r = sim::simulate(*p, 0, options, &rec);
    REQUIRE_MESSAGE(r.error.empty(), r.error);
    io::RunInfo info;
    info.trace = true;
    const std::string error = io::write_outputs(dir, *p, 0, r, rec.take(), info);
    REQUIRE_MESSAGE(error.empty(), error);
}

}  // namespace sdv::test
