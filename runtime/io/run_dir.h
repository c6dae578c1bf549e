// Reading a run directory (the outputs of `sdv run -o`) back, as `sdv view` and `sdv plot` do:
// users pass such directories around, so every file is checked as untrusted input, and a
// problem is one error naming the file and the line.
#pragma once

#include <string>
#include <string_view>

namespace sdv::io {

// The header of trajectories.csv (runtime/io/recorder.cpp writes it).
inline constexpr std::string_view kTrajectoriesHeader = "time,tick,vehicle,kind,x,y,yaw,speed,accel,s,d,lane,maneuver";

// The highest tick a report shows: 100,000 (55 min at 30 Hz). The viewer's data holds a time per
// tick up to the last, so a higher tick is refused: one row at tick 99,999,999 (166 bytes) asked
// for 2.2 GB, and at 1,000,000 the page's data is 5 MB of it, whatever the rows.
inline constexpr long kMaxReportTicks = 100'000;

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
// 0 to kMaxReportTicks, the time and the 7 columns from x to d numbers as the outputs write them
// (is_plain_number). Returns "" or what is wrong, e.g. "column 'x' is not a number: 'abc'".
std::string parse_trajectory_row(std::string_view line, TrajectoryRow& row);

// A number as the outputs write them, which is also a JSON number: an optional '-', digits
// without a leading zero (but "0"), then optionally '.' and digits. No exponent, nan or inf.
bool is_plain_number(std::string_view text);

}  // namespace sdv::io
