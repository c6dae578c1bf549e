// JUnit XML of runs and sweeps (see junit.h).
#include "runtime/io/junit.h"

#include <cmath>

#include "runtime/catalog/catalog.h"
#include "runtime/io/text.h"

namespace sdv::io {
namespace {

constexpr auto num = catalog::format_number;

std::string unit_of(const ir::Scenario& s, size_t root) {
    const auto& e = s.expects[static_cast<size_t>(s.expect_roots[root])];
    if (e.kind != ir::Expect::Kind::call || e.function < 0) return "";
    const auto& def = catalog::expectations()[static_cast<size_t>(e.function)];
    if (def.boolean) return "";
    return std::string(catalog::si_unit(def.result));
}

}  // namespace

std::string junit_xml(const std::vector<JUnitSuite>& suites) {
    size_t tests = 0, failures = 0, errors = 0;
    for (const auto& s : suites) {
        for (const auto& c : s.cases) {
            ++tests;
            failures += c.failure ? 1 : 0;
            errors += c.error ? 1 : 0;
        }
    }
    std::string out = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
    out += "<testsuites tests=\"" + std::to_string(tests) + "\" failures=\"" + std::to_string(failures) +
           "\" errors=\"" + std::to_string(errors) + "\">\n";
    for (const auto& s : suites) {
        size_t f = 0, e = 0;
        double t = 0;
        for (const auto& c : s.cases) {
            f += c.failure ? 1 : 0;
            e += c.error ? 1 : 0;
            t += c.time;
        }
        out += "  <testsuite name=\"" + xml_text(s.name) + "\" tests=\"" + std::to_string(s.cases.size()) +
               "\" failures=\"" + std::to_string(f) + "\" errors=\"" + std::to_string(e) + "\" skipped=\"0\" time=\"" +
               num(t) + "\">\n";
        if (!s.properties.empty()) {
            out += "    <properties>\n";
            for (const auto& [k, v] : s.properties) {
                out += "      <property name=\"" + xml_text(k) + "\" value=\"" + xml_text(v) + "\"/>\n";
            }
            out += "    </properties>\n";
        }
        for (const auto& c : s.cases) {
            out += "    <testcase name=\"" + xml_text(c.name) + "\" classname=\"" + xml_text(c.classname) + "\" time=\"" +
                   num(c.time) + "\"";
            if (!c.failure && !c.error && c.output.empty()) {
                out += "/>\n";
                continue;
            }
            out += ">\n";
            if (c.failure) out += "      <failure message=\"" + xml_text(*c.failure) + "\" type=\"expectation\"/>\n";
            if (c.error) out += "      <error message=\"" + xml_text(*c.error) + "\" type=\"runtime\"/>\n";
            if (!c.output.empty()) out += "      <system-out>" + xml_text(c.output) + "</system-out>\n";
            out += "    </testcase>\n";
        }
        out += "  </testsuite>\n";
    }
    out += "</testsuites>\n";
    return out;
}

std::string expectation_message(const ir::Scenario& scenario, size_t root, const sim::ExpectResult& e) {
    std::string measured;
    if (e.value) {
        const std::string u = unit_of(scenario, root);
        measured = "measured " + num(*e.value) + (u.empty() ? "" : " " + u);
    } else {
        for (const auto& p : e.parts) {
            if (!measured.empty()) measured += ", ";
            measured += p.text + (p.value ? " = " + num(*p.value) : p.time ? " at " + num(*p.time) + " s" : "") +
                        (p.holds ? " (true)" : " (false)");
        }
        measured = measured.empty() ? "measured nothing" : "measured " + measured;
    }
    return measured + "; expected " + e.text;
}

std::string run_junit(const ir::Program& program, int scenario, const sim::RunResult& r, const std::string& file) {
    const ir::Scenario& s = program.scenarios[static_cast<size_t>(scenario)];
    JUnitSuite suite;
    suite.name = s.name;
    suite.properties = {{"file", file}, {"seed", std::to_string(s.seed)}};
    if (!r.error.empty()) {
        JUnitCase c;
        c.name = "run";
        c.classname = s.name;
        c.error = r.error;
        suite.cases.push_back(c);
    }
    for (size_t k = 0; k < r.expectations.size(); ++k) {
        const auto& e = r.expectations[k];
        JUnitCase c;
        c.name = e.text;
        c.classname = s.name;
        c.time = r.duration;
        if (!r.error.empty()) {
            c.error = "not evaluated: " + r.error;
        } else if (!e.passed) {
            c.failure = expectation_message(s, k, e);
        } else {
            c.output = expectation_message(s, k, e);
        }
        suite.cases.push_back(c);
    }
    return junit_xml({suite});
}

}  // namespace sdv::io
