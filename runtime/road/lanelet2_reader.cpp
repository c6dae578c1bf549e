#include "runtime/road/lanelet2_reader.h"

#include <GeographicLib/LocalCartesian.hpp>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <pugixml.hpp>
#include <set>
#include <sstream>

#include "runtime/road/lane_geometry.h"
#include "runtime/road/reader_text.h"

namespace sdv::road {
namespace {

// Limits that keep the work of reading a map proportional to its size: coordinates within
// 1,000 km of the origin, lanelets (sampled every 0.5 m) at most 50 km long, and at most 100 km of
// lanes in all (each lane's reference line is sampled every 0.25 m; without a total, a few KB of
// long lanelets made seconds of work), and as much of crosswalks and walkways.
constexpr double kMaxCoordinate = 1e6;
constexpr double kMaxLaneletLength = 50e3;
constexpr double kMaxTotalLength = 100e3;

using Id = long long;

struct Way {
    std::vector<Id> nodes;
    std::map<std::string, std::string> tags;
};

struct Member {
    std::string type, role;
    Id ref;
};

struct Relation {
    std::vector<Member> members;
    std::map<std::string, std::string> tags;
};

std::map<std::string, std::string> read_tags(const pugi::xml_node& e) {
    std::map<std::string, std::string> tags;
    for (auto t : e.children("tag"))
        tags[t.attribute("k").as_string()] = t.attribute("v").as_string();
    return tags;
}

bool parse_id(const char* text, Id& out) {
    char* end = nullptr;
    errno = 0;
    out = std::strtoll(text, &end, 10);
    return end != text && *end == '\0' && errno == 0;
}

// Speed limits as written in maps: "50", "50 km/h", "30 mph", "13.9 m/s" → m/s.
std::optional<double> parse_speed(const std::string& v) {
    char* end = nullptr;
    const double x = std::strtod(v.c_str(), &end);
    if (end == v.c_str() || !std::isfinite(x) || x <= 0) return std::nullopt;
    std::string unit(end);
    unit.erase(std::remove(unit.begin(), unit.end(), ' '), unit.end());
    if (unit.empty() || unit == "km/h" || unit == "kmh" || unit == "kph") return x / 3.6;
    if (unit == "mph") return x * 0.44704;
    if (unit == "m/s" || unit == "mps") return x;
    return std::nullopt;
}

using Tags = std::map<std::string, std::string>;

// ---- Lanelet2's rules (docs/design-notes.md, "Lanelet2 topology"; the functions named are
// Lanelet2's). Independently re-derived in scripts/lanelet2-golden.py.

// Attribute::asBool.
std::optional<bool> as_bool(const std::string& v) {
    if (v == "1" || v == "true" || v == "yes") return true;
    if (v == "0" || v == "false" || v == "no") return false;
    return std::nullopt;
}

bool starts_with(const std::string& s, const std::string& prefix) {
    return s.compare(0, prefix.size(), prefix) == 0;
}

// GenericTrafficRules.cpp: hasOverride / getOverride (the first tag, in key order, that the
// override key starts with).
bool has_override(const Tags& tags, const std::string& prefix) {
    return std::any_of(tags.begin(), tags.end(),
                       [&](const auto& t) { return starts_with(t.first, prefix); });
}

bool get_override(const Tags& tags, const std::string& prefix, const std::string& key,
                  bool fallback) {
    for (const auto& [k, v] : tags) {
        if (k.size() >= prefix.size() && starts_with(key, k)) return as_bool(v).value_or(fallback);
    }
    return fallback;
}

// GenericTrafficRules::canPass(lanelet) for participant "vehicle" under GermanVehicle (which
// has no regulatory element that forbids passing): isDrivingDir, then the participant
// overrides, then the subtype table of canPass(type, location).
bool vehicle_can_pass(const Tags& tags, bool inverted) {
    if (inverted) {
        std::optional<bool> one_way;
        if (auto it = tags.find("one_way"); it != tags.end()) one_way = as_bool(it->second);
        if (one_way) {
            if (*one_way) return false;
        } else if (!has_override(tags, "one_way") ||
                   get_override(tags, "one_way", "one_way:vehicle", true)) {
            return false;  // vehicles: one way unless tagged otherwise
        }
    }
    if (has_override(tags, "participant"))
        return get_override(tags, "participant", "participant:vehicle", false);
    auto it = tags.find("subtype");
    const std::string subtype = it == tags.end() ? "" : it->second;
    // Subtypes whose participants include a prefix of "vehicle": "" and road, highway,
    // play_street, exit. (emergency_lane is for "vehicle:emergency" only; bicycle_lane,
    // walkway, crosswalk, stairs, shared_walkway and unknown subtypes are not for vehicles.)
    return subtype.empty() || subtype == "road" || subtype == "highway" ||
           subtype == "play_street" || subtype == "exit";
}

enum class Change { none, to_left, to_right, both };

// GenericTrafficRules::laneChangeType for a vehicle along a lanelet's bound: the hard-coded
// lane_change, lane_change:left, lane_change:right tags, else the line's type and subtype;
// swapped when the lanelet uses the way inverted.
Change lane_change_type(const Tags& tags, bool inverted) {
    auto flag = [&](const char* k) { return as_bool(tags.at(k)).value_or(false); };
    Change c = Change::none;
    if (tags.count("lane_change")) {
        c = flag("lane_change") ? Change::both : Change::none;
    } else if (tags.count("lane_change:left")) {
        c = !flag("lane_change:left")                                      ? Change::none
            : tags.count("lane_change:right") && flag("lane_change:right") ? Change::both
                                                                           : Change::to_left;
    } else if (tags.count("lane_change:right")) {
        c = flag("lane_change:right") ? Change::to_right : Change::none;
    } else {
        auto get = [&](const char* k) {
            auto it = tags.find(k);
            return it == tags.end() ? std::string() : it->second;
        };
        const std::string type = get("type"), subtype = get("subtype");
        if (type == "line_thin" || type == "line_thick") {
            if (subtype == "dashed")
                c = Change::both;
            else if (subtype == "dashed_solid")
                c = Change::to_right;
            else if (subtype == "solid_dashed")
                c = Change::to_left;
        }
    }
    if (inverted && c == Change::to_left) return Change::to_right;
    if (inverted && c == Change::to_right) return Change::to_left;
    return c;
}

// geometry::align: signedDistance with Lanelet2's ProjectedPoint strategy (3D distances, the
// first segment with a strictly smaller distance wins; left/right from the 2D cross product,
// with the corner rule of internal::isLeftOf).
struct P3 {
    double x = 0, y = 0, z = 0;
    friend bool operator==(const P3&, const P3&) = default;
};

bool point_is_left_of(const P3& s1, const P3& s2, const P3& p) {
    return (s2.x - s1.x) * (p.y - s1.y) - (s2.y - s1.y) * (p.x - s1.x) > 0;
}

double signed_distance(const std::vector<P3>& ls, const P3& p) {
    double best = -1;
    P3 b1, b2, bp;
    for (size_t i = 0; i + 1 < ls.size(); ++i) {
        const P3 &s1 = ls[i], &s2 = ls[i + 1];
        const P3 v{s2.x - s1.x, s2.y - s1.y, s2.z - s1.z}, w{p.x - s1.x, p.y - s1.y, p.z - s1.z};
        const double c1 = w.x * v.x + w.y * v.y + w.z * v.z;
        P3 proj = s1;
        if (c1 > 0) {
            const double c2 = v.x * v.x + v.y * v.y + v.z * v.z;
            proj = c2 <= c1 ? s2
                            : P3{s1.x + c1 / c2 * v.x, s1.y + c1 / c2 * v.y, s1.z + c1 / c2 * v.z};
        }
        const double d =
            std::sqrt((p.x - proj.x) * (p.x - proj.x) + (p.y - proj.y) * (p.y - proj.y) +
                      (p.z - proj.z) * (p.z - proj.z));
        if (best < 0 || d < best) {
            best = d;
            b1 = s1;
            b2 = s2;
            bp = proj;
        }
    }
    bool left = point_is_left_of(b1, b2, p);
    if (b2 == bp) {
        const auto it = std::find(ls.begin(), ls.end(), b2);
        if (it != ls.end() && std::next(it) != ls.end()) {
            const P3& next = *std::next(it);
            if (left != point_is_left_of(b2, next, p) && left == point_is_left_of(b1, b2, next))
                left = !left;
        }
    }
    return left ? best : -best;
}

P3 middle_point(const std::vector<P3>& ls) {
    if (ls.size() > 2) return ls[ls.size() / 2];
    return {0.5 * (ls.front().x + ls.back().x), 0.5 * (ls.front().y + ls.back().y),
            0.5 * (ls.front().z + ls.back().z)};
}

// Which bounds Lanelet2's loader inverts: the left one when the right bound's middle point is
// not to its right; then the right one when the (aligned) left bound's middle point is not to
// its left. Each bound on its own: either, both or neither may be turned.
std::pair<bool, bool> align(std::vector<P3> left, const std::vector<P3>& right) {
    if ((left.size() <= 1 && right.size() <= 1) || left.empty() || right.empty())
        return {false, false};
    const bool invert_left = !(signed_distance(left, middle_point(right)) < 0) && left.size() > 1;
    if (invert_left) std::reverse(left.begin(), left.end());
    const bool invert_right = !(signed_distance(right, middle_point(left)) > 0) && right.size() > 1;
    return {invert_left, invert_right};
}

// A lanelet bound as Lanelet2 holds it: the way and whether it is used inverted.
struct Bound {
    Id way = 0;
    bool inverted = false;
    std::vector<Id> nodes;  // in the lanelet's direction
    bool same_line(const Bound& o) const { return way == o.way && inverted == o.inverted; }
    bool opposite_line(const Bound& o) const { return way == o.way && inverted != o.inverted; }
    Bound invert() const {
        Bound b{way, !inverted, nodes};
        std::reverse(b.nodes.begin(), b.nodes.end());
        return b;
    }
};

// ---- Pedestrian areas: crosswalk and walkway lanelets, walkway multipolygons.

// The strip between two bounds: the mid-line of the bounds resampled at the same arc-length
// fractions, oriented along `a` (b is turned when its ends lie the other way round), and the
// mean distance between them as its width.
struct Strip {
    std::vector<Vec2> centre, left, right;
    double width = 0;
};

// The length of the pedestrian areas read so far (each sampled every 0.5 m): at most
// kMaxTotalLength, as for lanes, so that a few KB of areas sharing long ways is no
// second of work.
struct AreaBudget {
    double used = 0;
    bool exceeded = false;
};

std::optional<Strip> strip_between(const std::vector<Vec2>& a, std::vector<Vec2> b, AreaBudget& budget) {
    if (a.size() < 2 || b.size() < 2) return std::nullopt;
    const double la = polyline_length(a), lb = polyline_length(b);
    if (la < 1e-3 || lb < 1e-3 || std::max(la, lb) > kMaxLaneletLength) return std::nullopt;
    budget.used += std::max(la, lb);
    if (budget.used > kMaxTotalLength) {
        budget.exceeded = true;
        return std::nullopt;
    }
    if (distance(a.front(), b.front()) + distance(a.back(), b.back()) >
        distance(a.front(), b.back()) + distance(a.back(), b.front()))
        std::reverse(b.begin(), b.end());
    const int n = samples_for(std::max(la, lb));
    const auto as = resample(a, n), bs = resample(b, n);
    Strip st;
    double a_side = 0;  // > 0: a lies to the left of the centre line
    for (size_t i = 0; i < as.size(); ++i) {
        st.centre.push_back(0.5 * (as[i] + bs[i]));
        st.width += distance(as[i], bs[i]) / n;
    }
    for (size_t i = 0; i + 1 < as.size(); ++i) a_side += cross(st.centre[i + 1] - st.centre[i], as[i] - st.centre[i]);
    if (polyline_length(st.centre) < 1e-3) return std::nullopt;
    st.left = a_side >= 0 ? a : b;
    st.right = a_side >= 0 ? b : a;
    return st;
}

// The outline of a multipolygon of outer ways only, chained end to end into one closed ring
// (the closing node not repeated); nullopt when the area is not that simple.
std::optional<std::vector<Id>> simple_ring(const Relation& rel, const std::map<Id, Way>& ways) {
    constexpr size_t kMaxPieces = 1000;  // the chaining is quadratic in the pieces
    std::vector<std::vector<Id>> pieces;
    for (const auto& m : rel.members) {
        auto w = ways.find(m.ref);
        if (m.type != "way" || m.role != "outer" || w == ways.end() || w->second.nodes.size() < 2) return std::nullopt;
        pieces.push_back(w->second.nodes);
    }
    if (pieces.empty() || pieces.size() > kMaxPieces) return std::nullopt;
    std::vector<Id> ring = pieces[0];
    std::vector<bool> used(pieces.size(), false);
    used[0] = true;
    for (size_t added = 1; added < pieces.size(); ++added) {
        bool found = false;
        for (size_t k = 0; k < pieces.size() && !found; ++k) {
            if (used[k] || (pieces[k].front() != ring.back() && pieces[k].back() != ring.back())) continue;
            if (pieces[k].front() != ring.back()) std::reverse(pieces[k].begin(), pieces[k].end());
            ring.insert(ring.end(), pieces[k].begin() + 1, pieces[k].end());
            used[k] = found = true;
        }
        if (!found) return std::nullopt;
    }
    if (ring.front() != ring.back()) return std::nullopt;
    ring.pop_back();
    if (ring.size() < 3) return std::nullopt;
    return ring;
}

// An area as a strip: its outline split at the two points farthest apart along its principal
// axis, the two halves taken as bounds (an approximation for areas far from strip-shaped).
std::optional<Strip> area_strip(const std::vector<Vec2>& ring, AreaBudget& budget) {
    Vec2 mean{};
    for (const auto& p : ring) mean = mean + (1.0 / static_cast<double>(ring.size())) * p;
    double sxx = 0, syy = 0, sxy = 0;
    for (const auto& p : ring) {
        const Vec2 d = p - mean;
        sxx += d.x * d.x;
        syy += d.y * d.y;
        sxy += d.x * d.y;
    }
    const double angle = 0.5 * std::atan2(2 * sxy, sxx - syy);
    const Vec2 axis{std::cos(angle), std::sin(angle)};
    size_t lo = 0, hi = 0;
    for (size_t i = 0; i < ring.size(); ++i) {
        if (dot(ring[i], axis) < dot(ring[lo], axis)) lo = i;
        if (dot(ring[i], axis) > dot(ring[hi], axis)) hi = i;
    }
    if (lo == hi) return std::nullopt;
    std::vector<Vec2> a, b;  // lo → hi one way round the ring, and the other way
    for (size_t i = lo;; i = (i + 1) % ring.size()) {
        a.push_back(ring[i]);
        if (i == hi) break;
    }
    for (size_t i = lo;; i = (i + ring.size() - 1) % ring.size()) {
        b.push_back(ring[i]);
        if (i == hi) break;
    }
    return strip_between(a, b, budget);
}

const std::set<std::string> kRoles = {"refers", "ref_line", "light_bulbs", "right_of_way",
                                      "yield",  "cancels",  "cancel_line"};
const std::set<std::string> kRegSubtypes = {"traffic_light", "right_of_way", "all_way_stop",
                                            "speed_limit", "traffic_sign"};

std::vector<Vec2> way_points(const Way& w, const std::map<Id, Vec2>& nodes) {
    std::vector<Vec2> pts;
    for (Id n : w.nodes) pts.push_back(nodes.at(n));
    return pts;
}

// A crosswalk or walkway lanelet as a strip between its bounds, oriented along its left bound
// as written (nullopt, with a warning, when the bounds give none; missing bounds are already
// errors).
std::optional<Strip> lanelet_strip(Id id, const Relation& rel, const std::map<Id, Way>& ways,
                                   const std::map<Id, Vec2>& nodes, AreaBudget& budget, std::vector<std::string>& warnings) {
    const Way* bound[2] = {nullptr, nullptr};
    for (const auto& m : rel.members) {
        auto w = ways.find(m.ref);
        if (m.type == "way" && w != ways.end() && (m.role == "left" || m.role == "right"))
            bound[m.role == "left" ? 0 : 1] = &w->second;
    }
    if (!bound[0] || !bound[1]) return std::nullopt;
    auto st = strip_between(way_points(*bound[0], nodes), way_points(*bound[1], nodes), budget);
    if (!st && !budget.exceeded) warnings.push_back("lanelet " + std::to_string(id) + ": " + rel.tags.at("subtype") +
                                " with degenerate bounds; ignored");
    return st;
}

// The pedestrians' signal of a crosswalk lanelet: the first traffic light it refers to.
int32_t crosswalk_light(const Relation& rel, const std::map<Id, int32_t>& light_index) {
    for (const auto& m : rel.members) {
        auto l = light_index.find(m.ref);
        if (m.role == "regulatory_element" && l != light_index.end()) return l->second;
    }
    return -1;
}

// What pedestrians use: crosswalk lanelets (Crosswalk) and walkway lanelets and simple walkway
// multipolygons (Walkway), each named by its relation id.
void add_pedestrian_areas(const std::map<Id, Vec2>& nodes, const std::map<Id, Way>& ways,
                          const std::map<Id, Relation>& rels, const std::vector<Id>& rel_order,
                          const std::map<Id, int32_t>& light_index, RoadNetwork& net,
                          std::vector<std::string>& errors, std::vector<std::string>& warnings) {
    AreaBudget budget;
    for (Id id : rel_order) {
        const Relation& rel = rels.at(id);
        auto tag = [&](const char* k) {
            auto t = rel.tags.find(k);
            return t == rel.tags.end() ? std::string() : t->second;
        };
        const std::string type = tag("type"), subtype = tag("subtype");
        if (type == "lanelet" && subtype == "crosswalk") {
            if (auto st = lanelet_strip(id, rel, ways, nodes, budget, warnings)) {
                Crosswalk cw;
                cw.name = std::to_string(id);
                cw.centre = std::move(st->centre);
                cw.left_bound = std::move(st->left);
                cw.right_bound = std::move(st->right);
                cw.width = st->width;
                cw.light = crosswalk_light(rel, light_index);
                net.crosswalks.push_back(std::move(cw));
            }
        } else if (subtype == "walkway" && (type == "lanelet" || type == "multipolygon")) {
            std::optional<Strip> st;
            if (type == "lanelet") {
                st = lanelet_strip(id, rel, ways, nodes, budget, warnings);
            } else if (auto ring = simple_ring(rel, ways)) {
                std::vector<Vec2> pts;
                for (Id n : *ring) pts.push_back(nodes.at(n));
                st = area_strip(pts, budget);
                if (!st && !budget.exceeded) warnings.push_back("multipolygon " + std::to_string(id) + ": degenerate walkway area; ignored");
            } else {
                warnings.push_back("multipolygon " + std::to_string(id) +
                                   ": walkway area is not one closed outline of outer ways; ignored");
            }
            if (st) net.walkways.push_back({std::to_string(id), std::move(st->centre), std::move(st->left), std::move(st->right), st->width});
        }
        if (budget.exceeded) {
            errors.push_back(type + " " + std::to_string(id) + ": the map's crosswalks and walkways are more than 100 km "
                             "long together; sdv reads maps of up to 100 km of them (cut the map to the scenario's area)");
            return;
        }
    }
}

}  // namespace

LoadResult load_lanelet2(const std::string& path, std::optional<GeoOrigin> origin) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        LoadResult r;
        r.errors.push_back("cannot read map file '" + path + "'");
        return r;
    }
    std::stringstream ss;
    ss << in.rdbuf();
    return parse_lanelet2(ss.str(), origin);
}

LoadResult parse_lanelet2(const std::string& xml, std::optional<GeoOrigin> origin) {
    LoadResult r;
    pugi::xml_document doc;
    const auto parsed = doc.load_buffer(xml.data(), xml.size());
    if (!parsed) {
        r.errors.push_back(std::string("not a valid OSM XML file: ") + parsed.description() +
                           " at byte " + std::to_string(parsed.offset));
        return r;
    }
    const auto osm = doc.child("osm");
    if (!osm) {
        r.errors.push_back("not an OSM file: no <osm> element");
        return r;
    }
    // Nodes (projected), ways, relations.
    std::map<Id, Vec2> nodes;
    std::map<Id, Way> ways;
    std::map<Id, Relation> rels;
    std::vector<Id> rel_order;
    std::map<Id, double> heights;  // the "ele" tag: Lanelet2 aligns bounds in 3D
    bool have_origin = origin.has_value();
    GeographicLib::LocalCartesian proj;
    for (auto n : osm.children("node")) {
        Id id;
        if (!parse_id(n.attribute("id").as_string(), id)) {
            r.errors.push_back("node with an invalid id '" +
                               std::string(n.attribute("id").as_string()) + "'");
            continue;
        }
        const auto tags = read_tags(n);
        // Each a number and nothing more: strtod (and pugixml's as_double, which Lanelet2's
        // loader uses) read "8.:5461" as 8 and moved the node tens of kilometres without a word.
        auto not_number = [&](const char* what, const std::string& text) {
            r.errors.push_back("node " + std::to_string(id) + ": " + what + " '" + text + "' is not a number");
        };
        if (auto e = tags.find("ele"); e != tags.end()) {
            const auto h = parse_number(e->second.c_str());
            if (!h) {
                not_number("ele", e->second);
                continue;
            }
            heights[id] = *h;
        }
        if (tags.count("local_x") && tags.count("local_y")) {
            const std::string& tx = tags.at("local_x");
            const std::string& ty = tags.at("local_y");
            const auto x = parse_number(tx.c_str()), y = parse_number(ty.c_str());
            if (!x || !y) {
                r.errors.push_back("node " + std::to_string(id) + ": local_x / local_y are not numbers ('" + tx +
                                   "', '" + ty + "')");
                continue;
            }
            if (std::fabs(*x) > kMaxCoordinate || std::fabs(*y) > kMaxCoordinate) {
                r.errors.push_back("node " + std::to_string(id) + ": local coordinates (" + tx + ", " + ty +
                                   ") are more than 1,000 km from the map's origin");
                continue;
            }
            nodes[id] = Vec2{*x, *y};
            continue;
        }
        const std::string lat_text = n.attribute("lat").as_string(), lon_text = n.attribute("lon").as_string();
        const auto lat_read = parse_number(lat_text.c_str()), lon_read = parse_number(lon_text.c_str());
        if (!lat_read || !lon_read) {
            if (!lat_read) not_number("lat", lat_text);
            if (!lon_read) not_number("lon", lon_text);
            continue;
        }
        const double lat = *lat_read, lon = *lon_read;
        if (std::fabs(lat) > 90 || std::fabs(lon) > 180) {
            r.errors.push_back("node " + std::to_string(id) + ": invalid coordinates (lat " + lat_text + ", lon " +
                               lon_text + ")");
            continue;
        }
        if (!have_origin) {
            origin = GeoOrigin{lat, lon, 0};
            have_origin = true;
        }
        if (nodes.empty()) proj.Reset(origin->lat, origin->lon, origin->alt);
        double x, y, z;
        proj.Forward(lat, lon, origin->alt, x, y, z);
        if (!std::isfinite(x) || !std::isfinite(y) || std::fabs(x) > kMaxCoordinate || std::fabs(y) > kMaxCoordinate) {
            r.errors.push_back("node " + std::to_string(id) + ": more than 1,000 km from the map's origin");
            continue;
        }
        nodes[id] = {x, y};
    }
    if (origin) r.origin = *origin;
    for (auto w : osm.children("way")) {
        Id id;
        if (!parse_id(w.attribute("id").as_string(), id)) continue;
        Way way;
        way.tags = read_tags(w);
        for (auto nd : w.children("nd")) {
            Id ref;
            if (!parse_id(nd.attribute("ref").as_string(), ref) || !nodes.count(ref)) {
                r.errors.push_back("way " + std::to_string(id) + ": refers to missing node " +
                                   nd.attribute("ref").as_string());
                continue;
            }
            way.nodes.push_back(ref);
        }
        ways[id] = std::move(way);
    }
    for (auto e : osm.children("relation")) {
        Id id;
        if (!parse_id(e.attribute("id").as_string(), id)) continue;
        Relation rel;
        rel.tags = read_tags(e);
        for (auto m : e.children("member")) {
            Member mem{m.attribute("type").as_string(), m.attribute("role").as_string(), 0};
            if (!parse_id(m.attribute("ref").as_string(), mem.ref)) {
                r.errors.push_back("relation " + std::to_string(id) +
                                   ": member with an invalid ref");
                continue;
            }
            rel.members.push_back(mem);
        }
        rels[id] = std::move(rel);
        rel_order.push_back(id);
    }
    auto points = [&](const Way& w) {
        std::vector<Vec2> pts;
        for (Id n : w.nodes) pts.push_back(nodes.at(n));
        return pts;
    };

    RoadNetwork net;
    // A vertex of Lanelet2's routing graph for a vehicle: a lanelet as loaded, or its inversion
    // when the lanelet is drivable both ways.
    struct LL {
        Id id;
        bool inverted;
        Bound left, right;
        LaneId lane;
        std::vector<Id> regs;
        std::vector<Id> stop_ways;
    };
    std::vector<LL> lls;
    auto points3 = [&](const std::vector<Id>& ids) {
        std::vector<P3> pts;
        for (Id n : ids) {
            auto h = heights.find(n);
            pts.push_back({nodes.at(n).x, nodes.at(n).y, h == heights.end() ? 0.0 : h->second});
        }
        return pts;
    };
    std::vector<size_t> both_ways;  // lanelets also drivable inverted
    for (Id id : rel_order) {
        const Relation& rel = rels[id];
        auto type = rel.tags.find("type");
        if (type == rel.tags.end() || type->second != "lanelet") continue;
        ++r.lanelets;
        const std::string where = "lanelet " + std::to_string(id);
        Id left = 0, right = 0;
        bool has_left = false, has_right = false;
        std::vector<Id> regs;
        std::vector<Id> stop_ways;  // GeoScenario maps name a lanelet's stop line directly
        for (const auto& m : rel.members) {
            if (m.role == "left") {
                left = m.ref;
                has_left = true;
            } else if (m.role == "right") {
                right = m.ref;
                has_right = true;
            } else if (m.role == "regulatory_element") {
                if (!rels.count(m.ref))
                    r.errors.push_back(where + ": refers to missing regulatory element " +
                                       std::to_string(m.ref));
                else
                    regs.push_back(m.ref);
            } else if (m.role == "stop_line") {
                if (!ways.count(m.ref))
                    r.errors.push_back(where + ": refers to missing way " + std::to_string(m.ref));
                else
                    stop_ways.push_back(m.ref);
            } else if (m.role.empty()) {
                r.warnings.push_back(where + ": member " + m.type + " " + std::to_string(m.ref) +
                                     " has no role; ignored");
            } else if (m.role != "centerline") {
                r.errors.push_back(where + ": unknown member role '" + m.role + "'");
            }
        }
        if (!has_left || !has_right) {
            r.errors.push_back(where + ": missing " + std::string(!has_left ? "left" : "right") +
                               " bound");
            continue;
        }
        if (!ways.count(left) || !ways.count(right)) {
            r.errors.push_back(where + ": refers to missing way " +
                               std::to_string(!ways.count(left) ? left : right));
            continue;
        }
        // Only lanelets a vehicle may drive become lanes
        // (RoutingGraphBuilder::getPassableLanelets).
        if (!vehicle_can_pass(rel.tags, false)) continue;
        const std::vector<Id>&ln = ways[left].nodes, &rn = ways[right].nodes;
        if (ln.size() < 2 || rn.size() < 2) {
            r.errors.push_back(where + ": degenerate " +
                               std::string(ln.size() < 2 ? "left" : "right") + " bound (way " +
                               std::to_string(ln.size() < 2 ? left : right) +
                               " has fewer than 2 nodes)");
            continue;
        }
        if (polyline_length(points(ways[left])) < 1e-3 ||
            polyline_length(points(ways[right])) < 1e-3) {
            r.errors.push_back(where + ": degenerate bound of zero length");
            continue;
        }
        // Orientation as Lanelet2's loader gives it (OsmHandlerLoad.cpp, loadLanelets:
        // geometry::align): each bound is turned when it lies on the wrong side of the other.
        const auto [inv_left, inv_right] = align(points3(ln), points3(rn));
        Bound lb{left, false, ln}, rb{right, false, rn};
        if (inv_left) lb = lb.invert();
        if (inv_right) rb = rb.invert();
        lls.push_back({id, false, lb, rb, kNoLane, regs, stop_ways});
        if (vehicle_can_pass(rel.tags, true)) both_ways.push_back(lls.size() - 1);
    }
    // Lanelets drivable both ways (one_way=no) are a second vertex, inverted: left and right
    // bounds swapped and reversed (RoutingGraphBuilder::appendBidirectionalLanelets, which
    // appends them after all the others).
    for (size_t i : both_ways) {
        const LL a = lls[i];
        lls.push_back(
            {a.id, true, a.right.invert(), a.left.invert(), kNoLane, a.regs, a.stop_ways});
    }
    r.both_ways = static_cast<int>(both_ways.size());
    double total_length = 0;
    for (LL& a : lls) {
        const Relation& rel = rels[a.id];
        const std::string where = "lanelet " + std::to_string(a.id);
        std::vector<Vec2> lp, rp;
        for (Id n : a.left.nodes) lp.push_back(nodes.at(n));
        for (Id n : a.right.nodes) rp.push_back(nodes.at(n));
        // Centre line: both bounds resampled at the same arc-length fractions and averaged.
        const double bound_length = std::max(polyline_length(lp), polyline_length(rp));
        if (!(bound_length <= kMaxLaneletLength)) {
            r.errors.push_back(where + ": a bound is " + std::to_string(static_cast<long long>(bound_length / 1000)) +
                               " km long; sdv reads lanelets up to 50 km (split it)");
            return r;  // the lanelets after it are not built: the map is refused
        }
        total_length += bound_length;
        if (total_length > kMaxTotalLength) {
            r.errors.push_back(where + ": the map's lanes are more than 100 km long together; sdv reads maps of up to "
                               "100 km of lanes (a lanelet drivable both ways counts twice; cut the map to the "
                               "scenario's area)");
            return r;
        }
        auto between = centre_between(lp, rp);
        Lane lane;
        lane.name = std::to_string(a.id) + (a.inverted ? kInvertedSuffix : "");
        lane.centre = std::move(between.centre);
        lane.left_bound = lp;
        lane.right_bound = rp;
        lane.width = between.width;
        const std::string location = rel.tags.count("location") ? rel.tags.at("location") : "urban";
        lane.speed_limit = location == "nonurban" ? 100 / 3.6 : 50 / 3.6;
        if (rel.tags.count("speed_limit")) {
            if (auto v = parse_speed(rel.tags.at("speed_limit")))
                lane.speed_limit = *v;
            else if (!a.inverted)
                r.warnings.push_back(where + ": unreadable speed_limit '" +
                                     rel.tags.at("speed_limit") + "'");
        }
        a.lane = net.add_lane(std::move(lane));
        if (!a.inverted) ++r.drivable;
    }
    // Successors: geometry::follows, by point identity: the end points of a vertex's left and
    // right bound are the start points of the other's (RoutingGraphBuilder::addFollowingEdges).
    std::map<std::pair<Id, Id>, std::vector<size_t>> starts;
    for (size_t i = 0; i < lls.size(); ++i)
        starts[{lls[i].left.nodes.front(), lls[i].right.nodes.front()}].push_back(i);
    auto following = [&](const LL& a) {
        auto it = starts.find({a.left.nodes.back(), a.right.nodes.back()});
        return it == starts.end() ? std::vector<size_t>{} : it->second;
    };
    std::map<std::pair<Id, Id>, size_t> ends;
    for (const auto& a : lls) ++ends[{a.left.nodes.back(), a.right.nodes.back()}];
    for (const auto& a : lls) {
        const auto next = following(a);
        for (size_t b : next) net.connect(a.lane, lls[b].lane);
        if (next.size() > 1) {
            // Lanelet2 refuses a routing graph where lanelets diverge and merge at once.
            if (ends[{a.left.nodes.back(), a.right.nodes.back()}] > 1) {
                r.warnings.push_back("lanelet " + std::to_string(a.id) +
                                     ": lanelets diverge and merge at its end (Lanelet2's routing "
                                     "graph rejects this)");
            }
        }
    }
    // Neighbours through shared bounds. Same direction: the other's right bound is this one's
    // left bound, the same way used the same way round (geometry::leftOf). Such a neighbour is
    // kept when the traffic rules let a vehicle change lanes across the bound
    // (GenericTrafficRules::canChangeLane: RoutingGraph::left/right); opposite direction: the
    // other uses the same way inverted on the same side (the neighbour test of
    // geometry::overlaps2d), kept when there is no same-direction lane change on that side.
    // Several candidates (overlapping lanelets): the smallest lanelet id, the lanelet before its
    // inversion.
    auto order = [&](size_t i) { return std::pair{lls[i].id, lls[i].inverted}; };
    auto pick = [&](const std::vector<size_t>& c) {
        return c.empty() ? std::optional<size_t>{}
                         : std::optional<size_t>{*std::min_element(
                               c.begin(), c.end(),
                               [&](size_t x, size_t y) { return order(x) < order(y); })};
    };
    std::map<Id, std::vector<size_t>> by_way;  // the vertices bounded by a way
    for (size_t i = 0; i < lls.size(); ++i) {
        by_way[lls[i].left.way].push_back(i);
        if (lls[i].right.way != lls[i].left.way) by_way[lls[i].right.way].push_back(i);
    }
    for (size_t i = 0; i < lls.size(); ++i) {
        const LL& a = lls[i];
        const auto next = following(a);
        for (const bool left_side : {true, false}) {
            const Bound& b = left_side ? a.left : a.right;
            const Change c = lane_change_type(ways[b.way].tags, b.inverted);
            const bool allowed =
                c == Change::both || c == (left_side ? Change::to_left : Change::to_right);
            std::vector<size_t> same, opposite;
            for (size_t j : by_way[b.way]) {
                if (j == i) continue;
                const LL& o = lls[j];
                const bool successor = std::find(next.begin(), next.end(), j) != next.end();
                if ((left_side ? o.right : o.left).same_line(b) && !successor && allowed)
                    same.push_back(j);
                if ((left_side ? o.left : o.right).opposite_line(b)) opposite.push_back(j);
            }
            Lane& lane = net.lane_mut(a.lane);
            LaneId& nb = left_side ? lane.left : lane.right;
            bool& same_direction = left_side ? lane.left_same_direction : lane.right_same_direction;
            if (auto s = pick(same)) {
                nb = lls[*s].lane;
                same_direction = true;
            } else if (auto o = pick(opposite)) {
                nb = lls[*o].lane;
                same_direction = false;
            }
        }
    }
    // Regulatory elements.
    std::map<Id, int32_t> light_index;
    for (Id id : rel_order) {
        const Relation& rel = rels[id];
        if (!rel.tags.count("type") || rel.tags.at("type") != "regulatory_element") continue;
        const std::string where = "regulatory element " + std::to_string(id);
        const std::string subtype = rel.tags.count("subtype") ? rel.tags.at("subtype") : "";
        if (!kRegSubtypes.count(subtype)) {
            r.warnings.push_back(where + ": subtype '" + subtype + "' is ignored");
            continue;
        }
        for (const auto& m : rel.members) {
            if (!kRoles.count(m.role))
                r.errors.push_back(where + ": unknown member role '" + m.role + "'");
            const bool exists = m.type == "way"    ? ways.count(m.ref) > 0
                                : m.type == "node" ? nodes.count(m.ref) > 0
                                                   : rels.count(m.ref) > 0;
            if (!exists)
                r.errors.push_back(where + ": member " + m.type + " " + std::to_string(m.ref) +
                                   " does not exist");
        }
        if (subtype == "traffic_light") {
            TrafficLight tl;
            tl.id = static_cast<int32_t>(net.lights.size());
            tl.name = std::to_string(id);
            Vec2 sum{};
            int count = 0;
            for (const auto& m : rel.members) {
                if (m.role == "refers" && m.type == "way" && ways.count(m.ref)) {
                    // GeoScenario scenarios bind their light programs by the light way's name.
                    if (auto nm = ways[m.ref].tags.find("name");
                        nm != ways[m.ref].tags.end() && !nm->second.empty()) {
                        tl.name = nm->second;
                    }
                    for (Id nd : ways[m.ref].nodes) {
                        sum = sum + nodes.at(nd);
                        ++count;
                    }
                }
            }
            if (count > 0) tl.position = (1.0 / count) * sum;
            light_index[id] = tl.id;
            net.lights.push_back(std::move(tl));
        }
    }
    // Attach regulatory elements and stop lines (ref_line) to the lanelets that refer to them.
    auto attach_stop_line = [&](const LL& a, Id way) {
        if (!ways.count(way) || ways[way].nodes.size() < 2) return;
        Lane& lane = net.lane_mut(a.lane);
        const auto pts = points(ways[way]);
        const Vec2 mid = 0.5 * (pts.front() + pts.back());
        const auto& ref = net.reference(a.lane);
        const FrenetState f = ref.project(mid);
        // One stop line per lanelet: the last its elements give (maps draw one per lanelet).
        if (f.s >= -2 && f.s <= ref.length() + 2 && std::fabs(f.d) < 0.5 * lane.width + 3) {
            lane.stop_lines.assign(1, StopLine{std::clamp(f.s, 0.0, ref.length()), {}});
        }
    };
    for (const LL& a : lls) {
        for (Id w : a.stop_ways) attach_stop_line(a, w);
        Lane& lane = net.lane_mut(a.lane);
        for (Id reg : a.regs) {
            const Relation& rel = rels[reg];
            const std::string subtype = rel.tags.count("subtype") ? rel.tags.at("subtype") : "";
            if (subtype == "traffic_light" && light_index.count(reg)) {
                lane.traffic_lights.push_back(light_index[reg]);
                net.lights[static_cast<size_t>(light_index[reg])].lanes.push_back(a.lane);
            }
            if (subtype == "all_way_stop") lane.all_way_stop = true;
            if (subtype == "speed_limit") {
                for (const auto& [k, v] : rel.tags) {
                    if (k == "speed_limit" || k == "sign_type") {
                        if (auto s = parse_speed(v)) lane.speed_limit = *s;
                    }
                }
            }
            // A right-of-way element's stop line belongs to its yielding lanelets only.
            bool yields = subtype != "right_of_way";
            for (const auto& m : rel.members) {
                if (m.role == "yield" && m.type == "relation" && m.ref == a.id) yields = true;
            }
            for (const auto& m : rel.members) {
                if (yields && m.role == "ref_line" && m.type == "way") attach_stop_line(a, m.ref);
            }
        }
    }
    // A lanelet's lights control its stop line.
    for (const LL& a : lls) {
        Lane& lane = net.lane_mut(a.lane);
        for (StopLine& line : lane.stop_lines) line.traffic_lights = lane.traffic_lights;
    }
    // Right of way: yield and priority lanelets.
    for (Id id : rel_order) {
        const Relation& rel = rels[id];
        if (!rel.tags.count("subtype") ||
            (rel.tags.at("subtype") != "right_of_way" && rel.tags.at("subtype") != "all_way_stop"))
            continue;
        RightOfWay row;
        for (const auto& m : rel.members) {
            if (m.type != "relation") continue;
            for (const LL& a : lls) {
                if (a.id != m.ref) continue;
                if (m.role == "yield") row.yield.push_back(a.lane);
                if (m.role == "right_of_way") row.priority.push_back(a.lane);
            }
        }
        const auto index = static_cast<int32_t>(net.rights_of_way.size());
        for (LaneId l : row.yield) net.lane_mut(l).right_of_way = index;
        for (LaneId l : row.priority) net.lane_mut(l).right_of_way = index;
        net.rights_of_way.push_back(std::move(row));
    }
    add_pedestrian_areas(nodes, ways, rels, rel_order, light_index, net, r.errors, r.warnings);
    if (r.errors.empty()) {
        if (auto crowded = crowded_place(net)) r.errors.push_back(*crowded);
    }
    if (r.errors.empty()) {
        mark_junctions(net);
        find_crossings(net);
    }
    if (r.drivable == 0 && r.errors.empty()) r.errors.push_back("the map has no drivable lanelet");
    if (r.errors.empty()) r.network = std::move(net);
    return r;
}

Vec2 project(const GeoOrigin& origin, double lat, double lon) {
    GeographicLib::LocalCartesian proj(origin.lat, origin.lon, origin.alt);
    double x, y, z;
    proj.Forward(lat, lon, origin.alt, x, y, z);
    return {x, y};
}

}  // namespace sdv::road
