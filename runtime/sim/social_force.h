// The pedestrian motion model: a social force model after GeoScenario Server's simulated
// pedestrians (sp/Pedestrian.py, SP.update_position_SFM and the *_interaction methods). The
// behaviour tree chooses where a pedestrian walks and how fast; this decides how it moves each
// tick: relaxation toward the desired velocity, repulsion and side-stepping from other
// pedestrians, repulsion from vehicles and static objects (oriented boxes) and a detour round
// those in the way.
//
// Where we differ from the reference, and why (each also noted at its constant or function):
// the desired speed falls off on the last metres (arrival without overshoot); the side-step
// direction follows the turning line of sight (the reference's rule makes offset walkers swap
// sides and touch); obstacles push with the reference's border strength over a longer range
// (its vehicle force is too weak to stop anyone); the detour round obstacles and the speed cap
// are additions; sliding friction, body compression between pedestrians and the "following"
// effect are left out (the reference disables or never adds the last two); a pedestrian who
// stands (desired speed 0, or at its target) does not evade others, only their bodies push it (in the reference
// standing pedestrians side-step one another for ever: two at their goals a metre apart kept
// drifting at a quarter metre per second).
//
// Pure functions of their arguments: no allocation, no randomness, no state between calls, so
// the simulation loop can run them for all pedestrians over one snapshot in any order.
#pragma once

#include <span>

#include "runtime/road/geometry.h"

namespace sdv::sim::social_force {

using road::Vec2;

// Every constant of the model. "Reference" below is GeoScenario Server, sp/Pedestrian.py
// (SP class) unless another file is named; values not from it say where they come from.
// Forces are in newtons as in the reference and are divided by `mass`, so the published
// constants can be compared one to one.
struct Params {
    // --- walking toward the target -------------------------------------------------------
    // Relaxation time τ of the desired force (v_desired − v)/τ [s]. Reference: accl_time = 0.5.
    double relaxation_time = 0.5;
    // Arrival: the desired speed is min(v0, distance/arrival_time) [s], so the pedestrian slows
    // down on its last metres and comes to rest on the target. Not in the reference (there the
    // behaviour tree switches to a Stop maneuver within 1.5 m, has_reached_point, and the
    // pedestrian then overshoots by about v·τ). 2.0 = 4τ, the smallest value for which the
    // linearised approach is critically damped (no overshoot, no oscillation).
    double arrival_time = 2.0;
    // Body mass [kg] that turns the reference's forces into accelerations. Reference draws
    // random.uniform(50, 80) per pedestrian; 65 is that range's mean (we draw nothing).
    double mass = 65.0;
    // Body radius [m] a caller should use for a pedestrian disc. Reference: SimConfig.py
    // PEDESTRIAN_RADIUS = 0.27 (Euro NCAP pedestrian target, 0.5 m × 0.6 m).
    double body_radius = 0.27;

    // --- other pedestrians (other_pedestrian_interaction) ----------------------------------
    // Body repulsion A·exp((r_ij − d_ij)/B) along the line of centres [N]. Reference: A = 1500.
    double ped_strength = 1500.0;
    // Its range B [m]. Reference: B = 0.08.
    double ped_range = 0.08;
    // Evasive effect, part 1: C·exp((r_ij − d_ij)/D) along the other's heading reflected about
    // one's own [N]. Reference: C = 12.
    double evade_reflect_strength = 12.0;
    // Its range D [m]. Reference: D = 0.35.
    double evade_reflect_range = 0.35;
    // Evasive effect, part 2: E·exp((r_ij − d_ij)/F) sideways (left or right of one's own
    // velocity, by the sign of v_i × v_j) [N]. Reference: E = 400.
    double evade_side_strength = 400.0;
    // Its range F [m]. Reference: F = 0.82.
    double evade_side_range = 0.82;
    // Anisotropy λ of the evasive effect [-]: weight λ + (1 − λ)(1 + cos φ)/2 where φ is the
    // angle between one's walking direction and the other pedestrian, so someone behind counts
    // λ times someone straight ahead. Not applied to pedestrians by the reference; 0.5 is the
    // reference's vehicle λ (vehicle_interaction, lambda_i).
    double ped_anisotropy = 0.5;

    // --- vehicles and static objects (vehicle_interaction, border_interaction) -------------
    // Repulsion A_v·exp((r_i − d)/B_v) from the box outline [N], d = distance to the outline.
    // The reference's vehicle values (A = 20 N, B = 0.1 m) give 0.3 m/s² at contact and never
    // stop anyone; we use its border strength A = 1500 N (border_interaction) instead.
    double obstacle_strength = 1500.0;
    // Its range B_v [m]. Not the reference's 0.1/0.08: 0.25 lets a pedestrian walking at up to
    // 2.5 m/s stop before touching a car instead of bouncing off it.
    double obstacle_range = 0.25;
    // Anisotropy λ_v [-]: weight λ + (1 − λ)(1 + cos θ)/2, θ between the vehicle's direction of
    // motion and the pedestrian seen from the vehicle's centre (ahead of a moving car counts
    // double). Reference: lambda_i = 0.5, but with θ from the heading even for a standing car;
    // here a standing obstacle weighs 1 all round.
    double obstacle_anisotropy = 0.5;
    // Body force φ·max(0, r_i − d) once the disc overlaps the box [N/m]. Reference:
    // border_interaction phi = 12000.
    double obstacle_body = 12000.0;
    // Detour: a push along the outline of an obstacle that stands in the way, scaled by how
    // squarely it does, E·exp((r_i − d)/F) with the pedestrians' evade_side_strength and
    // evade_side_range. Not in the reference (there a pedestrian facing a car broadside stops
    // for good). The side is kept once the pedestrian slides along the outline faster than
    // this [m/s].
    double detour_commit_speed = 0.01;

    // --- speed limit (not in the reference, which has none) --------------------------------
    // The speed is capped at min(max_speed, max(max_speed_factor·v0, min_speed_cap)).
    // Factor on the desired speed v0 [-]: Helbing & Molnár's 1.3 (also socialforce's
    // MAX_SPEED_MULTIPLIER).
    double max_speed_factor = 1.3;
    // Cap when v0 is small [m/s]: a standing pedestrian can still be pushed aside.
    double min_speed_cap = 1.0;
    // Absolute cap [m/s]: a sprint; above the reference's fastest desired speed (2 m/s
    // default × 2 in IncreaseWalkingSpeed / ReturnToEntrance, ManeuverModels.py).
    double max_speed = 5.0;

    // --- standing (not in the reference) ----------------------------------------------------
    // Within this distance of its target a pedestrian stands, as one with desired speed 0 does
    // [m]: its arrival speed is under 0.125 m/s there. A standing pedestrian does not evade
    // others or walk round obstacles; only body forces move it.
    double stand_distance = 0.25;
};

// Another pedestrian: a disc.
struct Neighbour {
    Vec2 p, v;
    double radius = 0.27;
};

// A vehicle or static object: an oriented box (centre, heading, full length and width).
struct Obstacle {
    Vec2 centre;
    double yaw = 0, length = 4.5, width = 1.8;
    Vec2 v;
};

struct State {
    Vec2 p, v;
};

// The total force per unit mass (m/s²) on a pedestrian of `radius` at `s` walking to `target` at
// `desired_speed` (0 = come to rest), from `peds` (not including itself) and `obstacles`.
// Finite for any finite input; coordinates beyond ±1e7 m and speeds beyond ±1e3 m/s are clamped.
Vec2 force(const Params& params, const State& s, double radius, Vec2 target, double desired_speed,
           std::span<const Neighbour> peds, std::span<const Obstacle> obstacles);

// One step of `dt` seconds: semi-implicit Euler (velocity first, then position with the new
// velocity), speed capped as Params says. Finite for any finite input.
State step(const Params& params, const State& s, Vec2 force, double desired_speed, double dt);

// Whether a pedestrian at `p` with this target and desired speed stands (Params::stand_distance).
bool standing(const Params& params, Vec2 p, Vec2 target, double desired_speed);

// The speed cap step() applies for `desired_speed`.
double speed_cap(const Params& params, double desired_speed);

// Signed distance from `p` to the outline of `o` (negative inside) and the outward unit normal
// there; exposed because tests and ground truth want the same geometry.
struct BoxContact {
    double distance;
    Vec2 normal;
};
BoxContact box_contact(const Obstacle& o, Vec2 p);

}  // namespace sdv::sim::social_force
