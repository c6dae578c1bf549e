// Reading a run directory (the outputs of `sdv run -o`) back, as `sdv view` and `sdv plot` do:
// users pass such directories around, so every file is checked as untrusted input, and a
// problem is one error naming the file and the line.
#pragma once

#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace sdv::io {

// The header of trajectories.csv (runtime/io/recorder.cpp writes it).
inline constexpr std::string_view kTrajectoriesHeader = "time,tick,vehicle,kind,x,y,yaw,speed,accel,s,d,lane,maneuver";

// The most ticks a report leaves without a row, up to its last: 100,000 (55 min at 30 Hz). The
// viewer's data holds a time per tick up to the last, so rows far apart would make it far larger
// than the run (one row at tick 99,999,999, 166 bytes, asked for 2.2 GB). sdv run writes a row at
// every tick while an agent is on the road, so a report of a run of any length is within it.
inline constexpr long kMaxEmptyTicks = 100'000;

// The highest tick of any run: a day (catalog::kMaxScenarioTime) at the highest traffic rate
// (1,000 Hz). Readers that keep only the rows (sdv diff --runs) take ticks up to it.
inline constexpr long kMaxRunTicks = 86'400'000;

// The largest magnitude of a number of trajectories.csv: under 10^12 (12 digits before the point;
// the outputs write metres within 1,000 km and seconds within a day), so every one reads as a
// finite double.
inline constexpr int kMaxNumberDigits = 12;

// The deepest JSON nesting of summary.json, road.json and a line of decisions.jsonl (sdv run
// writes at most 5 levels): deeper text is refused before it is parsed, as writing it into the
// report would recurse once per level (ir::json_depth).
inline constexpr int kMaxRunJsonDepth = 64;

// One row of trajectories.csv, its columns as the file's own text.
struct TrajectoryRow {
    std::string_view time, vehicle, kind, x, y, yaw, speed, accel, s, d, lane, maneuver;
    long tick = 0;
};

// Splits and checks one row (without its line break): 13 columns, the tick a whole number from
// 0 to max_tick, the time and the 7 columns from x to d numbers as the outputs write them
// (is_plain_number) of at most kMaxNumberDigits digits before the point. Returns "" or what is
// wrong, e.g. "column 'x' is not a number: 'abc'".
std::string parse_trajectory_row(std::string_view line, TrajectoryRow& row, long max_tick = kMaxRunTicks);

// Reads trajectories.csv as every reader of a run directory does (sdv view, sdv plot,
// sdv diff --runs): the header, then each row checked (parse_trajectory_row) and each agent with
// a row at every tick from its first to its last, as sdv run writes it (the viewer places an
// agent's values by tick from its first). A problem is one error naming the file and the row.
//
//     TrajectoryReader in(text, path);
//     TrajectoryRow r;
//     while (in.next(r)) use(r, in.agent());
//     if (!in.error().empty()) fail(in.error());
class TrajectoryReader {
public:
    // `text` must outlive the reader (rows are views into it); `file` names it in errors.
    TrajectoryReader(std::string_view text, std::string file, long max_tick = kMaxRunTicks);
    // The next row; false at the end of the file or at a problem (then error() is set).
    bool next(TrajectoryRow& row);
    // The agent of the last row: its index in the order of the agents' first rows.
    size_t agent() const { return agent_; }
    // "FILE:LINE: " of the last row, to locate a problem its reader finds.
    std::string where() const { return file_ + ":" + std::to_string(row_) + ": "; }
    const std::string& error() const { return error_; }

private:
    std::string_view rest_;
    std::string file_, error_;
    long max_tick_;
    size_t row_ = 0, agent_ = 0;
    std::map<std::string, size_t, std::less<>> by_name_;
    std::vector<long> last_tick_;  // per agent
};

// A number as the outputs write them, which is also a JSON number: an optional '-', digits
// without a leading zero (but "0"), then optionally '.' and digits. No exponent, nan or inf.
bool is_plain_number(std::string_view text);

}  // namespace sdv::io
