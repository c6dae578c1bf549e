// Physical dimensions and the unit spellings the language accepts. Every quantity in a .sdv
// file carries a unit; the compiler normalises it to SI with this table, and the catalog
// states each parameter's dimension with the same enum.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace sdv::catalog {

enum class Dim {
    none,       // a plain number (counts, weights, factors)
    length,     // m
    time,       // s
    speed,      // m/s
    accel,      // m/s²
    jerk,       // m/s³
    angle,      // rad
    ratio,      // a fraction; written with % (10 % = 0.1)
    frequency,  // Hz
};

std::string_view to_string(Dim dim);
// The canonical (SI) unit spelling used in messages and docs, e.g. "m/s²".
std::string_view si_unit(Dim dim);

struct Unit {
    std::string_view spelling;  // as written, canonical form (e.g. "m/s^2")
    Dim dim;
    double to_si;  // multiply a value in this unit by to_si to get SI
};

// Looks up a unit written in the source, after the compiler has normalised it to the canonical
// ASCII form: atoms joined by '/', powers written '^N' ("m/s^2", "km/h", "deg", "%").
std::optional<Unit> find_unit(std::string_view canonical);
// All accepted canonical spellings, for "did you mean" and the docs.
std::span<const Unit> all_units();
// True when `word` can start or continue a unit (m, km, s, h, ...): the parser uses it so that
// an identifier after a number is taken as a unit only when it is one.
bool is_unit_atom(std::string_view word);

}  // namespace sdv::catalog
