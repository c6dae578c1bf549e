// Fuzz target of `sdv diff --runs` (runtime/io/run_diff.h diff_runs): two run directories read
// as untrusted input. The input is the files of the two runs separated by NUL bytes, in this
// order: the first run's trajectories.csv and decisions.jsonl, the second's trajectories.csv and
// decisions.jsonl; files after the last part are absent. With two parts or fewer the second run
// is a copy of the first.
//
// Properties: a run that is refused says which file; both orders of the runs are refused or
// not alike, and when read they agree on whether the runs are equal, on the first tick that
// differs and its agents, and on the first decision that differs; a run read without error
// equals itself; the JSON output parses.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "runtime/io/run_diff.h"
#include "tests/fuzz/targets/scratch.h"
#include "tests/fuzz/targets/targets.h"

using namespace sdv;

namespace {

constexpr const char* kTarget = "run_diff";
constexpr const char* kFiles[] = {"trajectories.csv", "decisions.jsonl"};

void check_output(const io::RunDiff& d) {
    if (!d.error.empty() && d.error.find("trajectories.csv") == std::string::npos &&
        d.error.find("decisions.jsonl") == std::string::npos) {
        fuzz::fail(kTarget, "an error that names no file: " + d.error);
    }
    (void)io::render_text(d);
    if (!nlohmann::json::accept(io::render_json(d))) fuzz::fail(kTarget, "the JSON output does not parse");
}

std::vector<std::string> sorted(std::vector<std::string> v) {
    std::sort(v.begin(), v.end());
    return v;
}

}  // namespace

int sdv_fuzz_run_diff(const uint8_t* data, size_t size) {
    std::string_view bytes(reinterpret_cast<const char*>(data), size);
    const std::string root = fuzz::fresh_dir(kTarget);
    const std::string a = root + "/a", b = root + "/b";
    std::filesystem::create_directory(a);
    std::filesystem::create_directory(b);
    std::vector<std::string_view> parts;
    while (parts.size() < 4) {
        const size_t nul = bytes.find('\0');
        parts.push_back(bytes.substr(0, nul));
        if (nul == std::string_view::npos) break;
        bytes.remove_prefix(nul + 1);
    }
    for (size_t i = 0; i < parts.size(); ++i) {
        const size_t k = i < 2 ? i : i - 2;
        fuzz::write_file((i < 2 ? a : b) + "/" + kFiles[k], parts[i]);
        if (parts.size() <= 2) fuzz::write_file(b + "/" + kFiles[k], parts[i]);
    }
    const io::RunDiff f = io::diff_runs(a, b), r = io::diff_runs(b, a);
    check_output(f);
    check_output(r);
    if (f.error.empty() != r.error.empty()) fuzz::fail(kTarget, "one order of the runs is refused, the other not: " + f.error + r.error);
    if (!f.error.empty()) return 0;
    if (f.equal != r.equal) fuzz::fail(kTarget, "the runs are equal in one order only");
    if (f.first_tick != r.first_tick || sorted(f.vehicles) != sorted(r.vehicles)) {
        fuzz::fail(kTarget, "the orders disagree on the first tick that differs or its agents");
    }
    if (f.decision_detail.empty() != r.decision_detail.empty() ||
        (!f.decision_detail.empty() && (f.decision_time != r.decision_time || f.decision_vehicle != r.decision_vehicle))) {
        fuzz::fail(kTarget, "the orders disagree on the first decision that differs");
    }
    for (const std::string& dir : {a, b}) {
        const io::RunDiff self = io::diff_runs(dir, dir);
        if (!self.error.empty() || !self.equal) fuzz::fail(kTarget, "a run read without error differs from itself: " + io::render_text(self));
    }
    return 0;
}
