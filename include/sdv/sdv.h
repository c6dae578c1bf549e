/* sdv.h: the in-process C API of sdv (libsdv.so), co-simulation without a socket.
 *
 * One handle is one simulation of one scenario: load it, claim its external vehicles, then step
 * k -> k+1 with each claimed vehicle's state at k+1. Every SDV plans from the snapshot at k
 * (Jacobi steps), so results never depend on the caller's speed or thread counts; the network
 * server (`sdv run --cosim`) is the same session behind a socket. No global state: several
 * handles may live in one process, one thread per handle. C99; no callbacks; no exceptions cross
 * this boundary. Units are SI, positions are bounding-box centres in map metres (x east, y north),
 * yaw in radians counter-clockwise from +x. Documented in docs/cosim.md. */
#ifndef SDV_SDV_H
#define SDV_SDV_H

#include <stddef.h>
#include <stdint.h>

#if defined(_WIN32)
#define SDV_API __declspec(dllexport)
#else
#define SDV_API __attribute__((visibility("default")))
#endif

#ifdef __cplusplus
extern "C" {
#endif

#define SDV_API_VERSION 1000 /* major * 1000 + minor */

typedef struct sdv_sim sdv_sim; /* opaque */

typedef enum {
    SDV_OK = 0,
    SDV_ERR_ARG = -1,         /* a bad argument (NULL, non-finite value, struct_size too small) */
    SDV_ERR_STATE = -2,       /* not now: e.g. a step without a claimed vehicle's state, after the end */
    SDV_ERR_NOT_FOUND = -3,   /* no such (external) vehicle */
    SDV_ERR_SCENARIO = -4,    /* the scenario does not load or compile (the message has the diagnostics) */
    SDV_ERR_BUFFER = -5,      /* the caller's buffer is too small: *n holds the count needed */
    SDV_ERR_UNSUPPORTED = -6, /* not in this version (command control, OSI) */
    SDV_ERR_INTERNAL = -99
} sdv_status;

typedef enum { SDV_RUNNING = 1, SDV_ENDED_SUCCESS = 2, SDV_ENDED_FAILURE = 3, SDV_ENDED_TIMEOUT = 4 } sdv_run_state;
typedef enum { SDV_CONTROL_POSE = 1, SDV_CONTROL_COMMAND = 2 } sdv_control_mode;
typedef enum { SDV_KIND_CAR = 1, SDV_KIND_TRUCK = 2, SDV_KIND_PEDESTRIAN = 3, SDV_KIND_CYCLIST = 4, SDV_KIND_OBJECT = 5 } sdv_actor_kind;
typedef enum { SDV_EVENT_COLLISION = 1, SDV_EVENT_SCENARIO_END = 2, SDV_EVENT_MANEUVER = 3 } sdv_event_type;

#define SDV_FLAG_SEED 1u  /* use sdv_config.seed instead of the scenario's */
#define SDV_FLAG_TRACE 2u /* write decisions.jsonl */

typedef struct {
    uint32_t struct_size;      /* sizeof(sdv_config) */
    const char* scenario_path; /* .sdv, .sdvir or a GeoScenario .osm */
    const char* scenario_name; /* which scenario of the file; NULL: its only one */
    const char* output_dir;    /* run outputs (as `sdv run -o`); NULL: none */
    uint64_t seed;             /* with SDV_FLAG_SEED */
    uint32_t step_num, step_den; /* 0/0: the scenario's traffic rate; otherwise must equal it */
    uint32_t flags;
    int32_t threads;           /* planning threads; 0: 1 */
} sdv_config;

typedef struct {
    uint32_t struct_size;
    uint64_t id;
    double x, y, z, yaw, speed, accel, yaw_rate;
    double s, d;        /* on lane_id: s along it, d to the left of its centre */
    char lane_id[32];   /* empty: off every lane */
    int32_t active;
} sdv_actor_state;

typedef struct {
    uint32_t struct_size;
    uint64_t id;
    char name[64];
    int32_t kind;     /* sdv_actor_kind */
    int32_t external; /* declared external: claimable */
    double length, width, height, bbcenter_to_rear_x;
} sdv_actor_info;

typedef struct {
    uint32_t struct_size;
    uint64_t tick;
    int32_t type;  /* sdv_event_type */
    uint64_t a, b; /* collision: both actors; maneuver: the actor in a */
    char text[96]; /* scenario end: the reason; maneuver: its name; collision: the impact zone */
} sdv_event;

SDV_API uint32_t sdv_api_version(void);
SDV_API const char* sdv_version_string(void);

/* Loads and checks the scenario and takes tick 0. On SDV_ERR_SCENARIO / SDV_ERR_ARG *out is still
 * a handle (in a failed state) whose sdv_last_error says why; destroy it. */
SDV_API sdv_status sdv_create(const sdv_config* cfg, sdv_sim** out);
/* Writes the outputs (marked aborted) when sdv_finish was not called, and frees everything. */
SDV_API void sdv_destroy(sdv_sim* h);
/* The message of the last failed call on h ("" when none); valid until the next call on h. */
SDV_API const char* sdv_last_error(const sdv_sim* h);

/* Takes control of an external vehicle, before the first step. */
SDV_API sdv_status sdv_claim(sdv_sim* h, const char* actor_name, sdv_control_mode mode, uint64_t* id_out);
/* Two-call pattern: with cap too small (or buf NULL) returns SDV_ERR_BUFFER and *n = count. */
SDV_API sdv_status sdv_get_actor_info(const sdv_sim* h, sdv_actor_info* buf, size_t cap, size_t* n);
/* The state of claimed actor st->id at tick k+1 (the next sdv_step moves it there). */
SDV_API sdv_status sdv_set_external_state(sdv_sim* h, const sdv_actor_state* st);
/* v1.1: SDV_ERR_UNSUPPORTED. */
SDV_API sdv_status sdv_set_external_command(sdv_sim* h, uint64_t id, double accel, double steer);
/* k -> k+1. Every claimed actor needs its state for k+1 first. */
SDV_API sdv_status sdv_step(sdv_sim* h, sdv_run_state* rs);
SDV_API sdv_status sdv_get_tick(const sdv_sim* h, uint64_t* tick, double* time_s);
/* Every actor at the current tick, sorted by id. Two-call pattern as above. */
SDV_API sdv_status sdv_get_actor_states(const sdv_sim* h, sdv_actor_state* buf, size_t cap, size_t* n);
/* Events since the last call, in order; drains as many as fit (*n of them), SDV_ERR_BUFFER with
 * *n = the count left when buf is NULL or cap is 0 and events are pending. */
SDV_API sdv_status sdv_poll_events(sdv_sim* h, sdv_event* buf, size_t cap, size_t* n);
/* OSI is not built in this version: SDV_ERR_UNSUPPORTED. */
SDV_API sdv_status sdv_get_osi_ground_truth(sdv_sim* h, void* buf, size_t cap, size_t* len);
/* Ends the run now (at any tick): expectations evaluated, outputs written. */
SDV_API sdv_status sdv_finish(sdv_sim* h);
/* After sdv_finish: 1 when every expectation held, 0 otherwise. */
SDV_API sdv_status sdv_passed(const sdv_sim* h, int32_t* passed);

#ifdef __cplusplus
}
#endif

#endif /* SDV_SDV_H */
