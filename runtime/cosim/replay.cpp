// Replies are paired with the recorded ones in order: the server records each reply right after
// the request it answers, and an Error from below the protocol (FRAME_TOO_LARGE, TIMEOUT) appears
// as a server frame with no request before it, which replay reproduces with the same call.
#include "runtime/cosim/replay.h"

#include <google/protobuf/util/message_differencer.h>

namespace sdv::cosim {
namespace {

// Where a reply sits in the session, for the report: "tick 42 (seq 43)".
std::string locate(const v1::Envelope& e) {
    std::string where;
    if (e.has_step_result())
        where = "tick " + std::to_string(e.step_result().observation().tick());
    else if (e.has_welcome())
        where = "Welcome";
    else if (e.has_error())
        where = "Error " + code_name(e.error().code());
    else
        where = "frame";
    return where + " (seq " + std::to_string(e.seq()) + ")";
}

// The fields that differ, as protobuf's differencer words them (at most a few lines).
std::string describe(const v1::Envelope& recorded, const v1::Envelope& replayed) {
    std::string report;
    google::protobuf::util::MessageDifferencer d;
    d.ReportDifferencesToString(&report);
    d.Compare(recorded, replayed);
    constexpr size_t kMax = 2000;
    if (report.size() > kMax) report = report.substr(0, kMax) + "...\n";
    return report;
}

// Welcome without what may legitimately change between the recording and the replay.
std::string comparable_welcome(v1::Envelope e) {
    e.mutable_welcome()->clear_sdv_version();
    e.mutable_welcome()->clear_scenario();
    return encode(e, Encoding::binary);
}

}  // namespace

std::optional<RecordSummary> summarize_record(const std::string& path, std::string& error) {
    auto reader = RecordReader::open(path, error);
    if (!reader) return std::nullopt;
    RecordSummary out;
    out.header = reader->header();
    Direction d;
    std::string payload;
    for (;;) {
        const auto n = reader->next(d, payload, error);
        if (n == RecordReader::Next::end) return out;
        if (n == RecordReader::Next::error) return std::nullopt;
        if (d != Direction::server) continue;
        v1::Envelope e;
        std::string why;
        // The first sdv frame is the Welcome, or an Error that ended the session before one.
        if (decode(payload, out.header.encoding, e, why) && e.has_welcome())
            out.welcome = e.welcome();
        return out;
    }
}

ReplayResult replay(const std::string& path, Session& session, const WelcomeInfo& info) {
    ReplayResult out;
    auto reader = RecordReader::open(path, out.error);
    if (!reader) return out;
    const Encoding enc = reader->header().encoding;
    Protocol protocol(session, info, enc);
    std::optional<std::string> pending;  // the reply to the last client frame, not yet compared
    uint64_t position = 0;               // entries read

    auto compare = [&](const std::string& recorded, const std::string& replayed) {
        ++out.compared;
        v1::Envelope a, b;
        std::string why;
        const bool a_ok = decode(recorded, enc, a, why);
        const bool b_ok = decode(replayed, enc, b, why);
        const bool same = a_ok && b_ok && a.has_welcome() && b.has_welcome()
                              ? comparable_welcome(a) == comparable_welcome(b)
                              : recorded == replayed;
        if (same) return;
        ++out.differing;
        if (!out.first_difference.empty()) return;
        if (!a_ok) {
            out.first_difference =
                "entry " + std::to_string(position) + ": the recorded reply does not parse";
        } else {
            out.first_difference = "first difference at " + locate(a) + ", record entry " +
                                   std::to_string(position) + ":\n" +
                                   (b_ok ? describe(a, b) : "the replayed reply does not parse\n");
        }
    };

    Direction d;
    std::string payload;
    for (;;) {
        std::string error;
        const auto n = reader->next(d, payload, error);
        if (n == RecordReader::Next::end) break;
        ++position;
        if (n == RecordReader::Next::error) {
            // A session that was killed leaves an incomplete last entry; what came before counts.
            out.error = "record '" + path + "': " + error;
            break;
        }
        if (d == Direction::client) {
            if (pending) {
                // sdv answered the previous request; the record has no answer to it.
                ++out.compared;
                ++out.differing;
                if (out.first_difference.empty()) {
                    out.first_difference = "entry " + std::to_string(position) +
                                           ": the record has no reply where sdv sends one";
                }
                pending.reset();
            }
            if (protocol.closed()) {
                ++out.differing;
                if (out.first_difference.empty()) {
                    out.first_difference = "entry " + std::to_string(position) +
                                           ": the recorded client sent a frame after the replayed "
                                           "session had closed (" +
                                           protocol.outcome().ending + ")";
                }
                break;
            }
            pending = protocol.on_frame(payload);
            continue;
        }
        if (pending) {
            compare(payload, *pending);
            pending.reset();
            continue;
        }
        // A server frame without a request: an Error from below the protocol.
        v1::Envelope e;
        std::string why;
        if (decode(payload, enc, e, why) && e.has_error() &&
            (e.error().code() == v1::Error::FRAME_TOO_LARGE ||
             e.error().code() == v1::Error::TIMEOUT || e.error().code() == v1::Error::INTERNAL)) {
            compare(payload, protocol.fail(e.error().code(), e.error().message()));
        } else {
            ++out.compared;
            ++out.differing;
            if (out.first_difference.empty()) {
                out.first_difference = "entry " + std::to_string(position) +
                                       ": the record has an sdv frame that answers no request";
            }
        }
    }
    if (pending) {
        // The recorded server sent nothing here: its connection was gone by then.
        ++out.compared;
        ++out.differing;
        if (out.first_difference.empty())
            out.first_difference = "the record ends where sdv sends a reply";
    }
    // A record that ends while the session is open: the client went away (or sdv was killed).
    protocol.disconnected("the record ends without Bye");
    out.finish_error = protocol.finish();
    out.outcome = protocol.outcome();
    out.steps = protocol.steps();
    out.identical = out.error.empty() && out.differing == 0;
    return out;
}

}  // namespace sdv::cosim
