// The C API (include/sdv/sdv.h) over cosim::Session: argument checks, status codes and C structs
// only. It lives outside runtime/ because loading a scenario compiles it (compiler/), which the
// runtime may not include.
#include "include/sdv/sdv.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <exception>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "compiler/diag/diagnostic_engine.h"
#include "compiler/diag/render.h"
#include "compiler/diag/source_manager.h"
#include "compiler/gss/scenario.h"
#include "compiler/sema/compile.h"
#include "runtime/cosim/session.h"
#include "runtime/ir/ir_io.h"

struct sdv_sim {
    std::unique_ptr<sdv::cosim::Session> session;
    std::string error;
    bool finished = false;
};

namespace {

using sdv::cosim::Status;

// Loads .sdvir, GeoScenario (.osm, through its conversion) or .sdv; diagnostics into `error`.
std::shared_ptr<const sdv::ir::Program> load(const std::string& path, std::string& error) {
    namespace diag = sdv::diag;
    namespace compiler = sdv::compiler;
    if (path.size() > 6 && path.compare(path.size() - 6, 6, ".sdvir") == 0) {
        std::ifstream in(path, std::ios::binary);
        if (!in) {
            error = "cannot read '" + path + "'";
            return nullptr;
        }
        std::stringstream ss;
        ss << in.rdbuf();
        auto r = sdv::ir::read_ir(ss.str());
        if (!r.program) {
            error = path + ": error: " + r.error;
            return nullptr;
        }
        return std::make_shared<const sdv::ir::Program>(std::move(*r.program));
    }
    diag::SourceManager sm;
    diag::DiagnosticEngine diags;
    compiler::Compilation c;
    if (compiler::gss::is_geoscenario_path(path)) {
        auto conv = compiler::gss::convert_geoscenario(path, {}, sm, diags);
        if (conv && !diags.has_errors()) c = compiler::compile_source(path + ".sdv", conv->text, sm, diags, {});
    } else {
        c = compiler::compile_file(path, sm, diags, {});
    }
    if (diags.has_errors() || !c.program) {
        error = diag::render_all_text(diags, sm);
        if (error.empty()) error = "cannot load '" + path + "'";
        return nullptr;
    }
    return std::make_shared<const sdv::ir::Program>(std::move(*c.program));
}

sdv_status to_c(Status s) { return static_cast<sdv_status>(static_cast<int>(s)); }

void copy(char* dst, size_t cap, const std::string& src) {
    const size_t n = std::min(cap - 1, src.size());
    std::memcpy(dst, src.data(), n);
    dst[n] = '\0';
}

// Runs `fn` with the session, turning exceptions into SDV_ERR_INTERNAL.
template <typename Fn>
sdv_status guarded(sdv_sim* h, Fn fn) {
    if (h == nullptr) return SDV_ERR_ARG;
    if (!h->session) {
        if (h->error.empty()) h->error = "this simulation failed to load";
        return SDV_ERR_STATE;
    }
    try {
        h->error.clear();
        const sdv_status s = fn(*h->session);
        if (s != SDV_OK && h->error.empty()) h->error = h->session->last_error();
        return s;
    } catch (const std::exception& e) {
        h->error = std::string("internal error: ") + e.what();
        return SDV_ERR_INTERNAL;
    } catch (...) {
        h->error = "internal error";
        return SDV_ERR_INTERNAL;
    }
}

// The caller's array: SDV_ERR_BUFFER with the count needed when it is too small.
template <typename T, typename Src, typename Fill>
sdv_status fill_array(T* buf, size_t cap, size_t* n, const std::vector<Src>& src, Fill fill) {
    if (n == nullptr) return SDV_ERR_ARG;
    *n = src.size();
    if (buf == nullptr || cap < src.size()) return src.empty() ? SDV_OK : SDV_ERR_BUFFER;
    // An output array's elements are the library's to write: what the caller's memory held
    // (uninitialised, in C) is never read; each element's struct_size tells the caller the
    // layout written.
    for (size_t i = 0; i < src.size(); ++i) {
        T out{};
        out.struct_size = sizeof(T);
        fill(out, src[i]);
        buf[i] = out;
    }
    return SDV_OK;
}

}  // namespace

extern "C" {

uint32_t sdv_api_version(void) { return SDV_API_VERSION; }

const char* sdv_version_string(void) { return sdv::compiler::kCompilerVersion; }

sdv_status sdv_create(const sdv_config* cfg, sdv_sim** out) {
    if (out == nullptr) return SDV_ERR_ARG;
    *out = nullptr;
    sdv_sim* h = new (std::nothrow) sdv_sim;
    if (h == nullptr) return SDV_ERR_INTERNAL;
    *out = h;
    if (cfg == nullptr || cfg->struct_size < sizeof(sdv_config) || cfg->scenario_path == nullptr) {
        h->error = cfg == nullptr ? "no configuration" : cfg->scenario_path == nullptr ? "no scenario_path" : "struct_size is too small";
        return SDV_ERR_ARG;
    }
    try {
        auto program = load(cfg->scenario_path, h->error);
        if (!program) return SDV_ERR_SCENARIO;
        int index = 0;
        if (cfg->scenario_name != nullptr) {
            index = -1;
            for (size_t i = 0; i < program->scenarios.size(); ++i) {
                if (program->scenarios[i].name == cfg->scenario_name) index = static_cast<int>(i);
            }
            if (index < 0) {
                h->error = "no scenario '" + std::string(cfg->scenario_name) + "' in '" + cfg->scenario_path + "'";
                return SDV_ERR_NOT_FOUND;
            }
        } else if (program->scenarios.size() != 1) {
            h->error = "'" + std::string(cfg->scenario_path) + "' has " + std::to_string(program->scenarios.size()) +
                       " scenarios; choose one with scenario_name";
            return SDV_ERR_ARG;
        }
        const auto& sc = program->scenarios[static_cast<size_t>(index)];
        if (cfg->step_num != 0 || cfg->step_den != 0) {
            if (cfg->step_num == 0 || std::fabs(static_cast<double>(cfg->step_den) / cfg->step_num - sc.traffic_rate) > 1e-9) {
                h->error = "the step must be the scenario's: 1/" + std::to_string(std::llround(sc.traffic_rate)) + " s";
                return SDV_ERR_UNSUPPORTED;
            }
        }
        sdv::cosim::SessionOptions opts;
        if (cfg->flags & SDV_FLAG_SEED) opts.seed = cfg->seed;
        opts.trace = (cfg->flags & SDV_FLAG_TRACE) != 0;
        opts.threads = std::max(1, static_cast<int>(cfg->threads));
        if (cfg->output_dir != nullptr) opts.output_dir = cfg->output_dir;
        h->session = sdv::cosim::Session::create(program, index, opts, h->error);
        return h->session ? SDV_OK : SDV_ERR_SCENARIO;
    } catch (const std::exception& e) {
        h->error = std::string("internal error: ") + e.what();
        return SDV_ERR_INTERNAL;
    }
}

void sdv_destroy(sdv_sim* h) {
    if (h == nullptr) return;
    try {
        h->session.reset();  // writes the outputs as aborted when not finished
    } catch (...) {
    }
    delete h;
}

const char* sdv_last_error(const sdv_sim* h) { return h == nullptr ? "no simulation (NULL handle)" : h->error.c_str(); }

sdv_status sdv_claim(sdv_sim* h, const char* actor_name, sdv_control_mode mode, uint64_t* id_out) {
    return guarded(h, [&](sdv::cosim::Session& s) {
        if (actor_name == nullptr || id_out == nullptr) return SDV_ERR_ARG;
        if (mode != SDV_CONTROL_POSE && mode != SDV_CONTROL_COMMAND) return SDV_ERR_ARG;
        return to_c(s.claim(actor_name, mode == SDV_CONTROL_POSE ? sdv::cosim::ControlMode::pose : sdv::cosim::ControlMode::command,
                            *id_out));
    });
}

sdv_status sdv_get_actor_info(const sdv_sim* h, sdv_actor_info* buf, size_t cap, size_t* n) {
    return guarded(const_cast<sdv_sim*>(h), [&](sdv::cosim::Session& s) {
        return fill_array(buf, cap, n, s.actors(), [](sdv_actor_info& o, const sdv::cosim::ActorInfo& a) {
            o.id = a.id;
            copy(o.name, sizeof o.name, a.name);
            o.kind = static_cast<int32_t>(a.kind);
            o.external = a.external ? 1 : 0;
            o.length = a.length;
            o.width = a.width;
            o.height = a.height;
            o.bbcenter_to_rear_x = a.bbcenter_to_rear_x;
        });
    });
}

sdv_status sdv_set_external_state(sdv_sim* h, const sdv_actor_state* st) {
    return guarded(h, [&](sdv::cosim::Session& s) {
        if (st == nullptr || st->struct_size < sizeof(sdv_actor_state)) return SDV_ERR_ARG;
        sdv::cosim::ActorState a;
        a.id = st->id;
        a.x = st->x;
        a.y = st->y;
        a.z = st->z;
        a.yaw = st->yaw;
        a.speed = st->speed;
        a.accel = st->accel;
        a.yaw_rate = st->yaw_rate;
        a.s = st->s;
        a.d = st->d;
        a.active = st->active != 0;
        return to_c(s.set_external_state(a));
    });
}

sdv_status sdv_set_external_command(sdv_sim* h, uint64_t id, double accel, double steer) {
    (void)id;
    (void)accel;
    (void)steer;
    if (h == nullptr) return SDV_ERR_ARG;
    h->error = "control by command (acceleration, steering) is not supported yet; set states (sdv_set_external_state)";
    return SDV_ERR_UNSUPPORTED;
}

sdv_status sdv_step(sdv_sim* h, sdv_run_state* rs) {
    return guarded(h, [&](sdv::cosim::Session& s) {
        sdv::cosim::RunState state{};
        const Status st = s.step(state);
        if (rs != nullptr) *rs = static_cast<sdv_run_state>(static_cast<int>(state));
        return to_c(st);
    });
}

sdv_status sdv_get_tick(const sdv_sim* h, uint64_t* tick, double* time_s) {
    return guarded(const_cast<sdv_sim*>(h), [&](sdv::cosim::Session& s) {
        if (tick != nullptr) *tick = s.tick();
        if (time_s != nullptr) *time_s = s.time();
        return SDV_OK;
    });
}

sdv_status sdv_get_actor_states(const sdv_sim* h, sdv_actor_state* buf, size_t cap, size_t* n) {
    return guarded(const_cast<sdv_sim*>(h), [&](sdv::cosim::Session& s) {
        return fill_array(buf, cap, n, s.states(), [](sdv_actor_state& o, const sdv::cosim::ActorState& a) {
            o.id = a.id;
            o.x = a.x;
            o.y = a.y;
            o.z = a.z;
            o.yaw = a.yaw;
            o.speed = a.speed;
            o.accel = a.accel;
            o.yaw_rate = a.yaw_rate;
            o.s = a.s;
            o.d = a.d;
            copy(o.lane_id, sizeof o.lane_id, a.lane_id);
            o.active = a.active ? 1 : 0;
        });
    });
}

sdv_status sdv_poll_events(sdv_sim* h, sdv_event* buf, size_t cap, size_t* n) {
    return guarded(h, [&](sdv::cosim::Session& s) {
        if (n == nullptr) return SDV_ERR_ARG;
        // With no room, the count pending (nothing drained); else as many as fit, the rest
        // waits for the next call.
        if (buf == nullptr || cap == 0) {
            *n = s.pending_events();
            return *n == 0 ? SDV_OK : SDV_ERR_BUFFER;
        }
        const std::vector<sdv::cosim::Event> got = s.poll_events(cap);
        for (size_t i = 0; i < got.size(); ++i) {
            sdv_event o{};
            o.struct_size = sizeof(sdv_event);
            o.tick = got[i].tick;
            o.type = static_cast<int32_t>(got[i].type);
            o.a = got[i].a;
            o.b = got[i].b;
            copy(o.text, sizeof o.text, got[i].text);
            buf[i] = o;
        }
        *n = got.size();
        return SDV_OK;
    });
}

sdv_status sdv_get_osi_ground_truth(sdv_sim* h, void* buf, size_t cap, size_t* len) {
    (void)buf;
    (void)cap;
    if (len != nullptr) *len = 0;
    if (h == nullptr) return SDV_ERR_ARG;
    h->error = "OSI ground truth is not built into this version of sdv";
    return SDV_ERR_UNSUPPORTED;
}

sdv_status sdv_finish(sdv_sim* h) {
    return guarded(h, [&](sdv::cosim::Session& s) {
        const std::string e = s.finish("finished");
        if (!e.empty()) {
            h->error = e;
            return SDV_ERR_INTERNAL;
        }
        h->finished = true;
        return SDV_OK;
    });
}

sdv_status sdv_passed(const sdv_sim* h, int32_t* passed) {
    return guarded(const_cast<sdv_sim*>(h), [&](sdv::cosim::Session& s) {
        if (passed == nullptr) return SDV_ERR_ARG;
        const auto* r = s.result();
        if (r == nullptr || !h->finished) {
            const_cast<sdv_sim*>(h)->error = "the run has not finished (sdv_finish)";
            return SDV_ERR_STATE;
        }
        *passed = r->passed() ? 1 : 0;
        return SDV_OK;
    });
}

}  // extern "C"
