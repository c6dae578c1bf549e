#include "runtime/io/run_dir.h"

#include <nlohmann/json.hpp>

#include <array>

#include "runtime/io/text.h"

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

std::string parse_trajectory_row(std::string_view line, TrajectoryRow& row, long max_tick) {
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
    bool whole = !f[1].empty() && f[1].size() <= 9;
    for (char c : f[1]) whole = whole && c >= '0' && c <= '9';
    if (whole) tick = std::stol(std::string(f[1]));
    if (!whole || tick > max_tick) {
        return "tick '" + shown(f[1]) + "' is not a whole number from 0 to " + std::to_string(max_tick);
    }
    static constexpr const char* kNames[] = {"time", "tick", "vehicle", "kind", "x", "y", "yaw", "speed", "accel", "s", "d"};
    for (const size_t c : std::array<size_t, 8>{0, 4, 5, 6, 7, 8, 9, 10}) {
        if (!is_plain_number(f[c])) return std::string("column '") + kNames[c] + "' is not a number: '" + shown(f[c]) + "'";
        const size_t point = f[c].find('.');
        const size_t digits = (point == std::string_view::npos ? f[c].size() : point) - (f[c][0] == '-' ? 1 : 0);
        if (digits > static_cast<size_t>(kMaxNumberDigits)) {
            return std::string("column '") + kNames[c] + "' is over 10^" + std::to_string(kMaxNumberDigits) + ": '" + shown(f[c]) + "'";
        }
    }
    row = {f[0], f[2], f[3], f[4], f[5], f[6], f[7], f[8], f[9], f[10], f[11], f[12], tick};
    return "";
}

TrajectoryReader::TrajectoryReader(std::string_view text, std::string file, long max_tick)
    : rest_(text), file_(std::move(file)), max_tick_(max_tick) {
    const size_t eol = rest_.find('\n');
    const std::string_view header = rest_.substr(0, eol);
    rest_.remove_prefix(eol == std::string_view::npos ? rest_.size() : eol + 1);
    row_ = 1;
    if (header.substr(0, kTrajectoriesHeader.size()) != kTrajectoriesHeader) {
        error_ = file_ + ":1: unexpected header (expected " + std::string(kTrajectoriesHeader) + ")";
    }
}

bool TrajectoryReader::next(TrajectoryRow& row) {
    if (!error_.empty() || rest_.empty()) return false;
    const size_t eol = rest_.find('\n');
    const std::string_view line = rest_.substr(0, eol);
    rest_.remove_prefix(eol == std::string_view::npos ? rest_.size() : eol + 1);
    ++row_;
    if (std::string wrong = parse_trajectory_row(line, row, max_tick_); !wrong.empty()) {
        error_ = where() + wrong;
        return false;
    }
    const auto [it, fresh] = by_name_.try_emplace(std::string(row.vehicle), last_tick_.size());
    agent_ = it->second;
    if (fresh) {
        last_tick_.push_back(row.tick);
        return true;
    }
    if (row.tick != last_tick_[agent_] + 1) {
        error_ = where() + "agent " + json_text(nlohmann::json(std::string(row.vehicle.substr(0, 40)))) +
                 " at tick " + std::to_string(row.tick) + " after tick " + std::to_string(last_tick_[agent_]) +
                 " (an agent has a row at every tick from its first to its last)";
        return false;
    }
    last_tick_[agent_] = row.tick;
    return true;
}

}  // namespace sdv::io
