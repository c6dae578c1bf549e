#!/usr/bin/env python3
"""Golden tables of Lanelet2's road topology for vehicles, derived independently of sdv.

For every Lanelet2 map in shared/data (lanelet2/mapping_example.osm and every .osm in
geoscenario/maps/) this writes tests/golden/lanelet2/<map>.txt: one line per lanelet that is a
vertex of Lanelet2's routing graph for a vehicle under the German traffic rules (and one more,
named "<id>:inv", for the inverted lanelet when the lanelet is drivable both ways), with

    <name> left=<a>><b> right=<c>><d> succ=<names> lnb=<name>/<same|opposite> rnb=<name>/<same|opposite>

  left/right   first and last node id of the lanelet's left and right bound as Lanelet2 orients
               them (geometry::align on load; swapped and reversed for an inverted lanelet)
  succ         lanelets that follow (bounds start at the end points of this one's), sorted
  lnb / rnb    the neighbour on each side that sdv's RoadNetwork keeps: a same-direction lanelet
               reached by a permitted lane change (Lanelet2's RoutingGraph::left/right), else an
               opposite-direction lanelet sharing that bound inverted; "-" when none

The rules are those of Lanelet2's source (see docs/design-notes.md, "Lanelet2 topology"):
lanelet2_io/src/OsmHandlerLoad.cpp (loadLanelets: geometry::align),
lanelet2_core/include/lanelet2_core/geometry/impl/LineString.h (align, signedDistance),
lanelet2_core/include/lanelet2_core/geometry/GeometryHelper.h (ProjectedPoint),
lanelet2_core/include/lanelet2_core/geometry/impl/Lanelet.h (follows, leftOf, overlaps2d),
lanelet2_traffic_rules/src/GenericTrafficRules.cpp (canPass, isDrivingDir, canChangeLane,
laneChangeType), lanelet2_routing/src/RoutingGraphBuilder.cpp (vertices, following and sideway
edges). This script uses the Python standard library only and shares no code with sdv.

Usage: scripts/lanelet2-golden.py [--check] [--margins]
  --check    compare with the committed files instead of writing them (exit 1 on a difference)
  --margins  also print, per map, the lanelets whose orientation decision is nearly degenerate
"""
import math
import os
import sys
import xml.etree.ElementTree as ET

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
SHARED = os.path.join(os.path.dirname(ROOT), "shared", "data")
OUT = os.path.join(ROOT, "tests", "golden", "lanelet2")


def maps():
    out = [os.path.join(SHARED, "lanelet2", "mapping_example.osm")]
    gdir = os.path.join(SHARED, "geoscenario", "maps")
    out += [os.path.join(gdir, f) for f in sorted(os.listdir(gdir)) if f.endswith(".osm")]
    return out


# --- projection: WGS84 geodetic -> local east/north/up about the first node (GeographicLib's
# LocalCartesian, the projection sdv uses; the orientation decision does not depend on it except in
# degenerate cases, which --margins lists).
A = 6378137.0
F = 1 / 298.257223563
E2 = F * (2 - F)


def ecef(lat, lon, h):
    la, lo = math.radians(lat), math.radians(lon)
    n = A / math.sqrt(1 - E2 * math.sin(la) ** 2)
    return ((n + h) * math.cos(la) * math.cos(lo), (n + h) * math.cos(la) * math.sin(lo),
            (n * (1 - E2) + h) * math.sin(la))


class Enu:
    def __init__(self, lat0, lon0):
        self.o = ecef(lat0, lon0, 0.0)
        la, lo = math.radians(lat0), math.radians(lon0)
        self.sla, self.cla, self.slo, self.clo = math.sin(la), math.cos(la), math.sin(lo), math.cos(lo)

    def __call__(self, lat, lon):
        x, y, z = ecef(lat, lon, 0.0)
        dx, dy, dz = x - self.o[0], y - self.o[1], z - self.o[2]
        e = -self.slo * dx + self.clo * dy
        n = -self.sla * self.clo * dx - self.sla * self.slo * dy + self.cla * dz
        return e, n


# --- geometry (Lanelet2: geometry::align, signedDistance with the ProjectedPoint strategy)

def sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def left_of(s1, s2, p):  # internal::pointIsLeftOf: z of the cross product (x, y only)
    a, b = sub(s2, s1), sub(p, s1)
    return a[0] * b[1] - a[1] * b[0] > 0


def signed_distance(ls, p):
    best = None  # (d, s1, s2, projected); the first segment with a strictly smaller distance wins
    for s1, s2 in zip(ls, ls[1:]):
        v, w = sub(s2, s1), sub(p, s1)
        c1 = dot(w, v)
        if c1 <= 0:
            proj = s1
        else:
            c2 = dot(v, v)
            proj = s2 if c2 <= c1 else tuple(a + c1 / c2 * b for a, b in zip(s1, v))
        d = math.sqrt(dot(sub(p, proj), sub(p, proj)))
        if best is None or d < best[0]:
            best = (d, s1, s2, proj)
    d, s1, s2, proj = best
    is_left = left_of(s1, s2, p)
    if s2 == proj:
        i = ls.index(s2)
        if i + 1 < len(ls):
            nxt = ls[i + 1]
            if is_left != left_of(s2, nxt, p) and is_left == left_of(s1, s2, nxt):
                is_left = not is_left
    return d if is_left else -d


def middle(ls):
    if len(ls) > 2:
        return ls[len(ls) // 2]
    return tuple(0.5 * (a + b) for a, b in zip(ls[0], ls[-1]))


def align(left, right):
    """(invert left?, invert right?, the two signed distances) as geometry::align decides."""
    if (len(left) <= 1 and len(right) <= 1) or not left or not right:
        return False, False, 0.0, 0.0
    dl = signed_distance(left, middle(right))
    inv_left = not dl < 0 and len(left) > 1
    if inv_left:
        left = left[::-1]
    dr = signed_distance(right, middle(left))
    inv_right = not dr > 0 and len(right) > 1
    return inv_left, inv_right, dl, dr


# --- attributes (Lanelet2 Attribute::asBool; GenericTrafficRules getOverride/hasOverride)

def as_bool(v):
    if v in ("1", "true", "yes"):
        return True
    if v in ("0", "false", "no"):
        return False
    return None


def has_override(tags, prefix):
    return any(k.startswith(prefix) for k in tags)


def get_override(tags, prefix, override, default):
    for k in sorted(tags):
        if len(k) >= len(prefix) and override.startswith(k):
            b = as_bool(tags[k])
            return default if b is None else b
    return default


PASSABLE_SUBTYPES = {  # GenericTrafficRules::canPass(type, location): subtype -> participants
    "": ["vehicle"], "road": ["vehicle", "bicycle"], "highway": ["vehicle"], "bicycle_lane": ["bicycle"],
    "play_street": ["pedestrian", "bicycle", "vehicle"], "emergency_lane": ["vehicle:emergency"],
    "exit": ["pedestrian", "bicycle", "vehicle"], "walkway": ["pedestrian"], "crosswalk": ["pedestrian"],
    "stairs": ["pedestrian"], "shared_walkway": ["pedestrian", "bicycle"],
}
PARTICIPANT = "vehicle"


def driving_dir(tags, inverted):  # isDrivingDir
    if not inverted:
        return True
    if "one_way" in tags and as_bool(tags["one_way"]) is not None:
        return not as_bool(tags["one_way"])
    if has_override(tags, "one_way"):
        return not get_override(tags, "one_way", "one_way:" + PARTICIPANT, True)
    return PARTICIPANT == "pedestrian"


def can_pass(tags, inverted):  # GenericTrafficRules::canPass(lanelet); GermanVehicle: no regelem rule
    if not driving_dir(tags, inverted):
        return False
    if has_override(tags, "participant"):
        return get_override(tags, "participant", "participant:" + PARTICIPANT, False)
    who = PASSABLE_SUBTYPES.get(tags.get("subtype", ""))
    return who is not None and any(PARTICIPANT.startswith(p) for p in who)


VEHICLE_CHANGE = {("line_thin", "dashed"): "both", ("line_thick", "dashed"): "both",
                  ("line_thin", "dashed_solid"): "right", ("line_thick", "dashed_solid"): "right",
                  ("line_thin", "solid_dashed"): "left", ("line_thick", "solid_dashed"): "left"}


def lane_change_type(way_tags, inverted):  # GenericTrafficRules::laneChangeType (virtual not passable)
    def flag(k):
        b = as_bool(way_tags[k])
        return bool(b)
    if "lane_change" in way_tags:
        t = "both" if flag("lane_change") else "none"
    elif "lane_change:left" in way_tags:
        if flag("lane_change:left"):
            t = "both" if "lane_change:right" in way_tags and flag("lane_change:right") else "left"
        else:
            t = "none"
    elif "lane_change:right" in way_tags:
        t = "right" if flag("lane_change:right") else "none"
    else:
        t = VEHICLE_CHANGE.get((way_tags.get("type", ""), way_tags.get("subtype", "")), "none")
    if inverted:
        t = {"left": "right", "right": "left"}.get(t, t)
    return t


# --- one map

def derive(path):
    root = ET.parse(path).getroot()
    proj = None
    pts = {}
    for n in root.iter("node"):
        tags = {t.get("k"): t.get("v") for t in n.findall("tag")}
        lat, lon = float(n.get("lat")), float(n.get("lon"))
        if proj is None:
            proj = Enu(lat, lon)
        x, y = proj(lat, lon)
        z = float(tags["ele"]) if "ele" in tags else 0.0
        pts[int(n.get("id"))] = (x, y, z)
    ways = {}
    for w in root.iter("way"):
        ways[int(w.get("id"))] = ([int(nd.get("ref")) for nd in w.findall("nd")],
                                  {t.get("k"): t.get("v") for t in w.findall("tag")})
    vertices = []  # dicts: name, key, left/right = (way, inverted, node ids)
    margins = []
    for r in root.iter("relation"):
        tags = {t.get("k"): t.get("v") for t in r.findall("tag")}
        if tags.get("type") != "lanelet":
            continue
        lid = int(r.get("id"))
        left = [int(m.get("ref")) for m in r.findall("member") if m.get("role") == "left"]
        right = [int(m.get("ref")) for m in r.findall("member") if m.get("role") == "right"]
        if len(left) != 1 or len(right) != 1:
            continue
        lw, rw = left[0], right[0]
        lnodes, rnodes = ways[lw][0], ways[rw][0]
        inv_l, inv_r, dl, dr = align([pts[i] for i in lnodes], [pts[i] for i in rnodes])
        if can_pass(tags, False):
            margins.append((min(abs(dl), abs(dr)), lid))
        lb = (lw, inv_l, lnodes[::-1] if inv_l else lnodes)
        rb = (rw, inv_r, rnodes[::-1] if inv_r else rnodes)
        for inverted in (False, True):
            if not can_pass(tags, False) or not can_pass(tags, inverted):
                continue
            if inverted:
                v = {"name": f"{lid}:inv", "key": (1, lid), "left": (rb[0], not rb[1], rb[2][::-1]),
                     "right": (lb[0], not lb[1], lb[2][::-1])}
            else:
                v = {"name": str(lid), "key": (0, lid), "left": lb, "right": rb}
            vertices.append(v)
    # Successors: RoutingGraphBuilder::addFollowingEdges with geometry::follows.
    for u in vertices:
        u["succ"] = [v for v in vertices if u["left"][2][-1] == v["left"][2][0] and u["right"][2][-1] == v["right"][2][0]]
    # Neighbours.
    def bound_id(b):
        return (b[0], b[1])

    def pick(cands):
        return min(cands, key=lambda v: (v["key"][1], v["key"][0])) if cands else None

    for u in vertices:
        succ = {id(v) for v in u["succ"]}
        for side, other in (("left", "right"), ("right", "left")):
            b = u[side]
            # Same direction: leftOf(v, u) (v.rightBound == u.leftBound) for the left side; no sideway edge
            # where an edge (a successor) exists already; a lane change when canChangeLane allows it.
            same = [v for v in vertices if v is not u and id(v) not in succ and bound_id(v[other]) == bound_id(b)]
            allowed = []
            for v in same:
                t = lane_change_type(ways[b[0]][1], b[1])
                if (side == "left" and t in ("both", "left")) or (side == "right" and t in ("both", "right")):
                    allowed.append(v)
            # Opposite direction: the same bound inverted, on the same side (overlaps2d's neighbour test).
            opposite = [v for v in vertices if v is not u and bound_id(v[side]) == (b[0], not b[1])]
            nb = pick(allowed)
            u[side + "_nb"] = (nb["name"] + "/same") if nb else (pick(opposite)["name"] + "/opposite" if opposite else "-")
    lines = []
    for u in sorted(vertices, key=lambda v: (v["key"][1], v["key"][0])):
        succ = ",".join(sorted(v["name"] for v in u["succ"])) or "-"
        lines.append(f"{u['name']} left={u['left'][2][0]}>{u['left'][2][-1]} right={u['right'][2][0]}>{u['right'][2][-1]}"
                     f" succ={succ} lnb={u['left_nb']} rnb={u['right_nb']}")
    margins.sort()
    return lines, margins


def main():
    check = "--check" in sys.argv
    show_margins = "--margins" in sys.argv
    os.makedirs(OUT, exist_ok=True)
    bad = 0
    for m in maps():
        lines, margins = derive(m)
        name = os.path.splitext(os.path.basename(m))[0] + ".txt"
        target = os.path.join(OUT, name)
        text = "\n".join(lines) + "\n"
        if check:
            old = open(target).read() if os.path.exists(target) else ""
            if old != text:
                print(f"differs: {target}")
                bad = 1
        else:
            with open(target, "w") as f:
                f.write(text)
            print(f"{target}: {len(lines)} lanelets")
        if show_margins:
            print("  nearest orientation decisions (m, lanelet):", [(round(d, 3), i) for d, i in margins[:3]])
    return bad


if __name__ == "__main__":
    sys.exit(main())
