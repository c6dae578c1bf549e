#include "runtime/io/run_dir.h"

#include <array>

namespace sdv::io {

bool is_plain_number(std::string_view t) {
    size_t i = 0;
    if (i < t.size() && t[i] == '-') ++i;
    auto digits = [&] {
        const size_t start = i;
        while (i < t.size() && t[i] >= '0' && t[i] <= '9') ++i;
        return i - start;
    };
    const size_t first = i;
    const size_t whole = digits();
    if (whole == 0 || (whole > 1 && t[first] == '0')) return false;
    if (i < t.size() && t[i] == '.') {
        ++i;
        if (digits() == 0) return false;
    }
    return i == t.size();
}

std::string parse_trajectory_row(std::string_view line, TrajectoryRow& row) {
    std::array<std::string_view, 13> f;
    size_t n = 0, start = 0;
    for (size_t i = 0; i <= line.size(); ++i) {
        if (i < line.size() && line[i] != ',') continue;
        if (n == f.size()) return "expected 13 columns, found more";
        f[n++] = line.substr(start, i - start);
        start = i + 1;
    }
    if (n != f.size()) return "expected 13 columns, found " + std::to_string(n);
    // A shown text of a column: at most 40 bytes of it.
    auto shown = [](std::string_view t) { return std::string(t.substr(0, 40)) + (t.size() > 40 ? "..." : ""); };
    long tick = 0;
    bool whole = !f[1].empty() && f[1].size() <= 6;
    for (char c : f[1]) whole = whole && c >= '0' && c <= '9';
    if (whole) tick = std::stol(std::string(f[1]));
    if (!whole || tick > kMaxReportTicks) {
        return "tick '" + shown(f[1]) + "' is not a whole number from 0 to " + std::to_string(kMaxReportTicks);
    }
    static constexpr const char* kNames[] = {"time", "tick", "vehicle", "kind", "x", "y", "yaw", "speed", "accel", "s", "d"};
    for (const size_t c : std::array<size_t, 8>{0, 4, 5, 6, 7, 8, 9, 10}) {
        if (!is_plain_number(f[c])) return std::string("column '") + kNames[c] + "' is not a number: '" + shown(f[c]) + "'";
    }
    row = {f[0], f[2], f[3], f[4], f[5], f[6], f[7], f[8], f[9], f[10], f[11], f[12], tick};
    return "";
}

}  // namespace sdv::io
