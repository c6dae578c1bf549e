// JUnit XML, the test report format CI servers (Jenkins, GitLab, GitHub actions) and CARLA
// ScenarioRunner users read: <testsuites> of <testsuite> of <testcase>, a failing case with a
// <failure message=...>, a case that could not run with an <error>.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "runtime/ir/ir.h"
#include "runtime/sim/simulation.h"

namespace sdv::io {

struct JUnitCase {
    std::string name;
    std::string classname;
    double time = 0;                     // seconds (simulated: reports stay reproducible)
    std::optional<std::string> failure;  // the measured value and what was expected
    std::optional<std::string> error;    // the run could not be evaluated
    std::string output;                  // <system-out>
};

struct JUnitSuite {
    std::string name;
    std::vector<std::pair<std::string, std::string>> properties;
    std::vector<JUnitCase> cases;
};

std::string junit_xml(const std::vector<JUnitSuite>& suites);

// The failure message of one expectation: "measured 0.81 s; expected min_ttc(ego, v2) > 1.5 s".
std::string expectation_message(const ir::Scenario& scenario, size_t root, const sim::ExpectResult& e);

// One run (`sdv run --junit`): a suite with one test case per expectation, named by its text.
std::string run_junit(const ir::Program& program, int scenario, const sim::RunResult& result,
                      const std::string& file);

}  // namespace sdv::io
