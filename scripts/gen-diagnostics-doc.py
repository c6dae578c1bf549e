#!/usr/bin/env python3
"""Generates docs/diagnostics.md: one entry per diagnostic code, with its explanation (below)
and its example, which is the golden test of that code (input and the compiler's exact
output). Run after refreshing golden files; CI checks the committed file is up to date:

    scripts/gen-diagnostics-doc.py            # write docs/diagnostics.md
    scripts/gen-diagnostics-doc.py --check    # exit 1 if it would change
"""
import pathlib
import re
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
GOLDEN = ROOT / "tests" / "golden" / "lint"

# code: (title, explanation and fix)
ENTRIES = {
    "E0001": ("unexpected character or invalid encoding",
              "The file contains a character that cannot start any token (`$`, a control "
              "character), or is not valid UTF-8 (a binary file). Remove the character; save the "
              "file as UTF-8."),
    "E0002": ("unterminated string",
              "A string literal has no closing `\"` on its line. Close it; strings cannot span lines."),
    "E0003": ("syntax error",
              "The parser found a token it did not expect. The note lists what it expected at that "
              "point. After 20 syntax errors in one file the parser stops, with one more E0003 at the "
              "place of the last: \"too many syntax errors (20); stopping here\"."),
    "E0004": ("nesting too deep",
              "Braces, brackets, parentheses and decorators nest more than 128 levels, or one "
              "expectation has more than 256 `and` / `or` (each nests the expression a level "
              "deeper). Such input is refused before parsing so that it cannot exhaust the stack; "
              "split the tree into named subtrees, the expectation into several `expect`."),
    "E0005": ("number out of range",
              "A number literal does not fit a double (magnitude 1.8e308 and more)."),
    "E0006": ("cannot read file",
              "The file named on the command line does not exist or cannot be read."),
    "E0007": ("too many errors",
              "After 100 errors in one compilation the checker stops reporting; fix the first "
              "ones and run again."),
    "E0008": ("empty file", "The file holds no declaration at all (it is empty or only comments)."),
    "E0101": ("unknown tree",
              "A `subtree` or a vehicle's `tree` names a tree that is not declared in the file or "
              "its imports. Standard trees are `std.NAME` and need `import \"std/FILE.sdv\"`."),
    "E0102": ("unknown maneuver", "The maneuver is not in the catalog (`sdv catalog`)."),
    "E0103": ("unknown condition", "The condition is not in the catalog (`sdv catalog`)."),
    "E0104": ("unknown parameter",
              "A maneuver, condition, tree or `parallel` has no parameter of that name. The note "
              "suggests the closest name."),
    "E0105": ("unknown vehicle",
              "A vehicle reference (in a tree used by the scenario, or in an expectation) names no "
              "vehicle of the scenario, and is not `ego`, `self` or a zone."),
    "E0106": ("unknown lane",
              "A lane reference does not fit the road: built-in roads number their lanes (1, 2, "
              "-1), junction lanes are named, and only junctions with traffic lights have lights."),
    "E0107": ("unknown import", "The imported file does not exist (standard library or relative path)."),
    "E0108": ("duplicate name",
              "Two trees, roads, vehicles, scenarios, tree parameters or node labels have the "
              "same name. The note points at the first one."),
    "E0109": ("unknown road", "The scenario's `road` names no road, junction or map."),
    "E0110": ("unknown node in an override",
              "A subtree reference overrides `label.field`, but the tree has no node with that "
              "label, or the node is not a maneuver or condition."),
    "E0111": ("unknown expectation", "The function in an `expect` is not in the catalog."),
    "E0112": ("unknown parameter type", "A tree parameter's type is not one of the language's types."),
    "E0113": ("unknown setting or kind",
              "A vehicle kind, scenario setting, or statement that does not apply here (a tree on "
              "a trajectory vehicle, say)."),
    "E0201": ("wrong unit",
              "The value's unit has the wrong dimension for the parameter (`speed = 5 m`), or a "
              "tree parameter of one type is passed where another is expected."),
    "E0202": ("missing unit", "A physical quantity was written without its unit. Only 0 may omit it."),
    "E0203": ("unknown unit", "The unit is not in the unit table (see language.md)."),
    "E0204": ("wrong kind of value",
              "A string, a name or a list where a number is expected (or the reverse), a "
              "comparison on a true/false expectation, or a number where a whole number is needed."),
    "E0205": ("not sampleable",
              "A range or `samples` on a parameter that cannot be sampled (see the catalog's "
              "sampleable column), or on a scenario setting."),
    "E0206": ("invalid choice", "The word is not one of the parameter's choices; the note lists them."),
    "E0207": ("invalid arithmetic",
              "Arithmetic on quantities (`20 m + 25 m * i`, `(20 + 25 * i) m`, docs/language.md "
              "\"Many agents\") adds terms of different dimensions, multiplies or divides into a "
              "dimension the language has no unit for (a length times a length), divides by zero, "
              "puts a unit after a parenthesis that already holds one, or names something other "
              "than the index of a repeated agent. In a repeated agent the error is reported once, "
              "at the template, with a note naming the instances it failed for."),
    "E0301": ("value out of range",
              "The value (or an end of its range) lies outside the physical range the catalog "
              "allows: a negative duration, a zero jerk limit, 1e308 m/s."),
    "E0302": ("invalid sample count", "Sample counts are whole numbers from 1 to 100."),
    "E0303": ("lane outside the road", "The lane index does not exist on the built-in road."),
    "E0304": ("invalid range",
              "An interval whose lower end is above its upper end, a negative spread, or samples "
              "without a range."),
    "E0305": ("too many candidates",
              "The product of a maneuver's sample counts exceeds 20,000 candidate trajectories "
              "per planning cycle."),
    "E0306": ("tree too large",
              "A vehicle's tree, with its subtrees inlined, has more than 10,000 nodes, or the "
              "trees of all the agents of one scenario more than 1,000,000, or their nodes' paths "
              "(each names the trees above the node, `t/sub/keep_velocity`) more than 100,000,000 "
              "characters. Each reference to a subtree inlines it again, so a tree that references "
              "another twice, which references a third twice, and so on, doubles at every level: "
              "13 such levels pass 10,000 nodes. Reference a large subtree once (a `fallback` or "
              "`sequence` can hold what the two references did), or give fewer agents a large tree."),
    "E0401": ("missing required parameter",
              "A required maneuver or condition parameter, or a tree parameter without default, "
              "is not given."),
    "E0402": ("subtree cycle", "A tree contains itself through subtree references."),
    "E0403": ("unreachable child",
              "In a fallback, a child that always succeeds (an open-ended maneuver, or a sequence "
              "of them) hides every child after it."),
    "E0404": ("no maneuver", "No path through the tree selects a maneuver."),
    "E0405": ("tree root", "A tree must have exactly one root node; wrap several in a sequence or fallback."),
    "E0406": ("exclusive parameters", "Two parameters that exclude each other are both given."),
    "E0407": ("missing alternative", "The condition needs at least one of a group of parameters."),
    "E0408": ("duplicate argument", "The same parameter is given twice."),
    "E0410": ("empty composite", "A fallback, sequence or parallel without children."),
    "E0411": ("tree of the other agent kind",
              "A pedestrian's tree uses a vehicle's leaf, or a vehicle's tree a pedestrian's: "
              "pedestrians walk by the catalog's pedestrian maneuvers and conditions, vehicles "
              "drive by theirs (`sdv catalog` says which leaf is for whom; conditions such as "
              "`sim_time` and `reached_goal` are for any agent)."),
    "E0501": ("no road", "A scenario must name its road, junction or map with `road NAME`."),
    "E0502": ("vehicles overlap",
              "Two vehicles start with overlapping footprints: on the same lane, their rectangles "
              "(length along the lane, width across it, about their start) share an area; touching "
              "nose to tail or side by side is no overlap. Vehicles placed by `at (X, Y)` and "
              "trajectories whose first waypoint is after 0 s are not checked. The error is at each "
              "vehicle that overlaps one behind it (whose back is further back along the lane; of "
              "two at the same place, the one declared first), naming one of those: a vehicle on "
              "top of several others gets one error, and `n` vehicles at one place get `n - 1` "
              "(of a template, one error naming the instances). The check takes time in `n log n` "
              "for `n` vehicles, wherever they are."),
    "E0503": ("off the road", "A position lies outside the road (before its start, past its end, or beyond its lane)."),
    "E0504": ("duplicate setting", "A setting or statement is given twice."),
    "E0505": ("sdv without tree", "An `sdv` vehicle needs a `tree`."),
    "E0506": ("missing start", "A vehicle needs a `start` (or a trajectory with two waypoints or more)."),
    "E0507": ("more than one ego", "A scenario has at most one ego."),
    "E0508": ("expectation arity", "An expectation function got the wrong number of vehicles."),
    "E0509": ("invalid expectation window",
              "The time window at the end of an `expect` statement is not one: `during` needs an "
              "interval `A .. B` with A before B, `after` and `before` one time; times are not "
              "negative, not sampled or spread, and the window starts before the scenario's "
              "timeout. `fallback_used`, `fallback_share` and `timeout()` are counted over the "
              "whole run and take no window."),
    "E0510": ("map file not found", "The map's `file` does not exist (paths are relative to the .sdv file)."),
    "E0511": ("invalid repeated agent",
              "The range of a repeated agent (`vehicle v[1..50]`) is not two whole numbers without "
              "unit (0 or more), is empty (the lower bound above the upper), declares more than "
              "10,000 agents, or the scenario's agents, templates expanded, exceed 100,000."),
    "E0512": ("repeated ego",
              "The ego is declared with a range (`ego e[1..3]`): a scenario has one ego. Declare "
              "the others as `vehicle NAME[...]`."),
    "E0601": ("unknown vary parameter",
              "A path in a `vary` block names nothing the campaign can vary. Paths are `seed`, "
              "`timeout`, `rate.traffic|planning|latency|sensor_range`, `VEHICLE.speed|length|width`, "
              "`VEHICLE.start` (its `s`), `VEHICLE.start.offset` (or `.x`, `.y`, `.heading` of a point), "
              "the same for `goal`, and arguments of the vehicle's tree call: `VEHICLE.tree.PARAM` or "
              "`VEHICLE.tree.LABEL.PARAM`. The note suggests the closest path."),
    "E0602": ("empty vary domain",
              "A varied parameter has no value to take: a range whose lower end is above its upper "
              "end, a count below 2 (a single value is a set: `[x]`), a standard deviation that is "
              "not positive, levels of a whole-number parameter that are not whole, a block that "
              "varies nothing, or `sample random|latin` with a count of 0."),
    "E0603": ("invalid sampling",
              "`sample grid` runs every combination of levels: each parameter needs a set or a range "
              "with a `count`, and the grid must stay under 1,000,000 variants. A distribution, or a "
              "range without a count, is sampled: write `sample random N` or `sample latin N`."),
    "E0604": ("duplicate vary",
              "A parameter is varied twice, or a scenario has more than one `vary` block."),
    "E0605": ("cannot vary",
              "The checker compiles the scenario at the ends and the middle of each domain and "
              "requires every number of the scenario to follow the parameter linearly, so that a "
              "variant is the compiled scenario plus bindings. This fails when a value is clipped "
              "(a spread whose lower end would fall below 0) or when the parameter changes nothing "
              "(a tree parameter no node reads). A value written as a range or list cannot be varied "
              "either. Values of the domain the scenario cannot take are reported with the code of "
              "the check they fail (E0301, E0503, ...), at the vary block."),
    "E0901": ("inconsistent indentation (.btree)",
              "A line of a GeoScenario behavior tree closes a block at an indentation that no "
              "enclosing line has. Indent each child one level deeper than its composite."),
    "E0902": ("unknown maneuver configuration class (.btree)",
              "A `maneuver` names an MConfig class sdv does not map (see docs/geoscenario.md)."),
    "E0903": ("unknown MConfig parameter (.btree)",
              "A field the MConfig class does not have; the reference fails on it too "
              "(\"Could not instantiate tree\")."),
    "E0904": ("unknown condition (.btree)", "A condition the mapping of docs/geoscenario.md does not know."),
    "E0905": ("missing subtree (.btree)",
              "No NAME.btree on the search path: each `--btree-path DIR`, then the directory of "
              "the scenario or .btree file, then each `btrees/` directory in the scenario's "
              "directory and its parents (the reference's layout); in each, NAME.btree, then "
              "sdv/NAME.btree for a vehicle's tree, sp/NAME.btree for a pedestrian's "
              "(docs/geoscenario.md). The note lists the directories."),
    "E0906": ("invalid value (.btree)",
              "A value of the wrong form: a constant where a number is expected, a malformed "
              "MP(...)/LT(...) sampler, a tuple of the wrong length; or a number outside the range of "
              "the catalog parameter it sets, either end of a spread included (MP's ±b %, LT's "
              "±0.75 m or ±1.75 m), a sample count over 100 or a normal sampling's σ not above 0 "
              "(the converted text would not compile)."),
    "E0907": ("subtree cycle (.btree)", "A behavior tree refers to itself through its subtrees."),
    "E0908": ("override of an unknown node (.btree)",
              "A subtree reference overrides a maneuver node the subtree does not have."),
    "E0909": ("override changes the class (.btree)",
              "An override gives a node another MConfig class; sdv overrides change parameters only."),
    "E0910": ("not a GeoScenario file", "The scenario is not well-formed XML, has no <osm> element, or is "
              "not GeoScenario version 2."),
    "E0911": ("missing or invalid GeoScenario tag",
              "An element lacks a required tag (vid, btree, route, lanelet, origin, ...) or a tag "
              "has a malformed value, or one the converted .sdv text could not hold (a time over a "
              "day, trajectory times that do not increase, a map path that is not UTF-8). The message "
              "names the element."),
    "E0912": ("unknown GeoScenario reference",
              "A vehicle names a route or trajectory the file does not define, a way refers to a "
              "missing node, or the map is not found (give its directory with `--map-dir`)."),
    "E0913": ("unsupported GeoScenario element",
              "An element or tree leaf sdv cannot simulate: an element GeoScenario 2.0 does not define, the "
              "`at_desired_speed` and `past_crosswalk_halfway` conditions of a pedestrian tree, a `gap` "
              "condition without a distance or time, or a tree that never selects a maneuver."),
    "W0001": ("too many warnings",
              "After 100 warnings in one compilation the rest are counted, not shown: this note "
              "(severity `note`, no location) gives their number, and the warning counts include "
              "them: the summary line (\"103 warnings generated.\" after 100 listed), the "
              "`\"warnings\"` field of `--format json` (its `diagnostics` array lists the 100) and "
              "the summary of `sdv lint` on a terminal. A warning promoted to an error "
              "(`-Werror`) counts towards the 100 errors of E0007 instead. Silence a kind with "
              "`-Wno-NAME`, or fix the first ones and run again."),
    "W0101": ("unused-tree", "A tree of the main file is used by no scenario (only when the file has a scenario)."),
    "W0102": ("unused-parameter", "A tree parameter is never referenced in the tree."),
    "W0103": ("unused-import", "Nothing from an import is used (only when the file has a scenario)."),
    "W0104": ("no-expectations", "A scenario without `expect`: its run always passes."),
    "W0901": ("gss-ignored-parameter",
              "A .btree condition or MConfig parameter that sdv (and, for conditions, the "
              "reference) ignores."),
    "W0902": ("gss-extra-tree", "A .btree file holds more than one tree; only the first is used."),
    "W0903": ("gss-unknown-type",
              "An agent type GeoScenario does not define: like the reference, sdv makes such a vehicle a neutral "
              "(motionless) one and such a pedestrian a path pedestrian."),
    "W0904": ("gss-ignored-element",
              "An element the reference's scenario setup does not read (egogoal, metric, trigger): ignored."),
    "W0905": ("gss-reconfigured-twice",
              "A subtree reference or a vehicle's `btconfig` reconfigures the same node twice. The later "
              "configuration replaces the earlier one whole, as the reference reconfigures the node once per "
              "entry; drop the entry that should not count."),
    "W0906": ("gss-unreachable",
              "A fallback of a .btree tree has a child after one that never fails: a keep-velocity, stop or "
              "reverse maneuver (MVelKeepConfig, MStopConfig, MReverseConfig), alone or in a sequence with "
              "conditions that always hold (set_target_lane), or a subtree whose root is one. The reference never "
              "ticks the children after it, and sdv's trees may not have unreachable children (E0403), so the "
              "converter leaves them out. Give the child before a condition that can fail, or drop the dead ones."),
}


def render():
    out = ["# Diagnostics", "",
           "Generated by `scripts/gen-diagnostics-doc.py` from the golden tests "
           "(tests/golden/lint/CODE_*); do not edit by hand.", "",
           "Every diagnostic has a stable code: `E00xx` syntax, `E01xx` names, `E02xx` types and "
           "units, `E03xx` values, `E04xx` trees, `E05xx` scenarios, `E06xx` campaigns (`vary`), `E09xx` GeoScenario inputs "
           "(.btree trees, .osm scenarios), `W01xx` and `W09xx` warnings, `W0001` the note "
           "that warnings were left out. Warnings "
           "are named; `-Wno-NAME` silences one, `-Werror=NAME` promotes one, `-Werror` all. "
           "`--format json` prints the same diagnostics as JSON: "
           "`{\"diagnostics\": [...], \"errors\": N, \"warnings\": M}`, each diagnostic with its "
           "`severity`, `code`, `name` (warnings), `message`, `file`, `line`, `column`, `end_line` "
           "and `end_column` (when it has a location) and `notes`; N and M are the counts of the summary line.", ""]
    for code, (title, text) in ENTRIES.items():
        out += [f"## {code}: {title}", "", text, ""]
        cases = sorted(GOLDEN.glob(code + "_*"))
        if not cases:
            continue
        case = cases[0]
        src = next((case / n for n in ("input.sdv", "input.btree", "input.osm") if (case / n).exists()), None)
        if src is not None:
            out += [f"Example ({case.relative_to(ROOT)}):", "", "```text",
                    src.read_text().rstrip("\n"), "```", ""]
        err = case / "expected.err"
        if err.exists():
            out += ["```text", err.read_text().rstrip("\n"), "```", ""]
    return "\n".join(out)


def main():
    text = render()
    path = ROOT / "docs" / "diagnostics.md"
    if "--check" in sys.argv:
        if not path.exists() or path.read_text() != text:
            print("docs/diagnostics.md is out of date: run scripts/gen-diagnostics-doc.py")
            return 1
        used = set(re.findall(r'"([EW]\d{4})"', "".join(
            p.read_text() for p in (ROOT / "compiler").rglob("*.cpp"))))
        missing = sorted(c for c in used if c not in ENTRIES)
        untested = sorted(c for c in ENTRIES if not list(GOLDEN.glob(c + "_*")))
        # A warning's title is its name, which -Wno-NAME and -Werror=NAME accept (cli/common.cpp).
        cli = (ROOT / "cli" / "common.cpp").read_text()
        names = set(re.findall(r'"([a-z0-9-]+)"', cli[cli.index("kWarningNames"):cli.index("};", cli.index("kWarningNames"))]))
        # W0001 is the note that warnings were left out, not a warning: it has no name.
        unnamed = sorted(c for c, (title, _) in ENTRIES.items()
                         if c.startswith("W") and c != "W0001" and title not in names)
        if missing or untested or unnamed:
            print("codes used but not documented:", missing)
            print("codes without a golden test:", untested)
            print("warnings whose name the command line does not accept (cli/common.cpp kWarningNames):", unnamed)
            return 1
        print(f"{len(ENTRIES)} codes documented and tested")
        return 0
    path.write_text(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
