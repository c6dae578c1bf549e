// The unit table. Spellings are canonical ASCII; the compiler maps "m/s²", "m/s2" and
// "m/s^2" to the same entry before the lookup.
#include "runtime/catalog/units.h"

#include <array>
#include <numbers>

namespace sdv::catalog {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

constexpr std::array kUnits = {
    Unit{"m", Dim::length, 1.0},          Unit{"km", Dim::length, 1000.0},
    Unit{"cm", Dim::length, 0.01},        Unit{"mm", Dim::length, 0.001},
    Unit{"s", Dim::time, 1.0},            Unit{"ms", Dim::time, 0.001},
    Unit{"min", Dim::time, 60.0},         Unit{"h", Dim::time, 3600.0},
    Unit{"m/s", Dim::speed, 1.0},         Unit{"km/h", Dim::speed, 1.0 / 3.6},
    Unit{"mph", Dim::speed, 0.44704},     Unit{"m/s^2", Dim::accel, 1.0},
    Unit{"m/s^3", Dim::jerk, 1.0},        Unit{"deg", Dim::angle, kDeg},
    Unit{"rad", Dim::angle, 1.0},         Unit{"%", Dim::ratio, 0.01},
    Unit{"Hz", Dim::frequency, 1.0},
};

constexpr std::array<std::string_view, 9> kAtoms = {"m", "km", "cm", "mm", "s",
                                                     "ms", "min", "h", "mph"};
constexpr std::array<std::string_view, 5> kMoreAtoms = {"deg", "rad", "Hz", "s2", "s3"};

}  // namespace

std::string_view to_string(Dim dim) {
    switch (dim) {
        case Dim::none: return "number";
        case Dim::length: return "length";
        case Dim::time: return "time";
        case Dim::speed: return "speed";
        case Dim::accel: return "acceleration";
        case Dim::jerk: return "jerk";
        case Dim::angle: return "angle";
        case Dim::ratio: return "ratio";
        case Dim::frequency: return "frequency";
    }
    return "?";
}

std::string_view si_unit(Dim dim) {
    switch (dim) {
        case Dim::none: return "";
        case Dim::length: return "m";
        case Dim::time: return "s";
        case Dim::speed: return "m/s";
        case Dim::accel: return "m/s²";
        case Dim::jerk: return "m/s³";
        case Dim::angle: return "rad";
        case Dim::ratio: return "";
        case Dim::frequency: return "Hz";
    }
    return "";
}

std::optional<Unit> find_unit(std::string_view canonical) {
    for (const Unit& u : kUnits) {
        if (u.spelling == canonical) return u;
    }
    return std::nullopt;
}

std::span<const Unit> all_units() { return kUnits; }

bool is_unit_atom(std::string_view word) {
    for (auto a : kAtoms) {
        if (a == word) return true;
    }
    for (auto a : kMoreAtoms) {
        if (a == word) return true;
    }
    return false;
}

}  // namespace sdv::catalog
