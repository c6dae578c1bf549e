// `sdv replay-cosim RECORD`: a built-in client that plays a recorded session (record.h) back
// against a fresh Session of the same scenario and seed, and checks that sdv answers every
// recorded request with the same bytes (docs/cosim.md "Record and replay"). NPC behaviour is
// deterministic given the client's inputs, so any recorded ADS run becomes a regression test that
// needs no ADS. The recorded frames go through the same protocol state machine as on the wire
// (no socket: the wire adds nothing that could change a reply).
#pragma once

#include <optional>
#include <string>

#include "runtime/cosim/protocol.h"
#include "runtime/cosim/record.h"

namespace sdv::cosim {

// What the CLI needs before it can build the session to replay against.
struct RecordSummary {
    RecordHeader header;
    std::optional<v1::Welcome> welcome;  // the recorded Welcome (none: no Hello was accepted)
};

// Reads a record's header and its Welcome; nullopt with `error` when it is unreadable.
std::optional<RecordSummary> summarize_record(const std::string& path, std::string& error);

struct ReplayResult {
    std::string error;             // the record could not be read (nothing compared past it)
    bool identical = false;        // every reply equal to the recorded one
    uint64_t compared = 0;         // sdv frames compared
    uint64_t differing = 0;        // of which differed
    std::string first_difference;  // "tick 42 (seq 43): ..." with the fields that differ
    uint64_t steps = 0;
    Protocol::Outcome
        outcome;               // how the replayed session ended (as the recorded one, if identical)
    std::string finish_error;  // the outputs could not be written
};

// Replays the record at `path` over `session` (created for the recorded scenario and seed). Feeds
// every client frame, compares every reply with the recorded one, and finishes the session as the
// recorded one ended. Welcome is compared without sdv_version and scenario (a replay may run a
// newer sdv, from another directory); everything else byte for byte.
ReplayResult replay(const std::string& path, Session& session, const WelcomeInfo& info);

}  // namespace sdv::cosim
