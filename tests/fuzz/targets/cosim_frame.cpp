// Fuzz target of the co-simulation readers: what `sdv run --cosim` reads from a client and what
// `sdv replay-cosim` reads from a record, over the scenario of the co-simulation tests
// (tests/cli/data/cosim_highway.sdv, embedded at build time).
//
// An input starting with 'H' is a record (runtime/cosim/record.h): written to a file, read as
// `sdv replay-cosim` reads it (summarize_record, then replay over a fresh session). Any other
// input is the byte stream of a connection: frames (runtime/cosim/framing.h read_frame), each
// payload decoded in both encodings (runtime/cosim/codec.h), then all of them fed to the
// protocol (runtime/cosim/protocol.h Protocol::on_frame over a fresh session, in JSON when the
// first payload starts with '{', else binary), as the server does. At most kMaxFrames frames
// (entries of a record) per input: a session's cost is linear in its steps, and a longer one
// finds nothing new.
//
// Property: an Envelope that decodes encodes deterministically: decoding its encoding and
// encoding that again gives the same bytes (record and replay rely on it). (In JSON after one
// round: protobuf's parser reads "-0" as +0.)
#include <google/protobuf/stubs/logging.h>
#include <sys/mman.h>
#include <unistd.h>

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "compiler/sema/compile.h"
#include "runtime/cosim/codec.h"
#include "runtime/cosim/framing.h"
#include "runtime/cosim/protocol.h"
#include "runtime/cosim/replay.h"
#include "runtime/cosim/session.h"
#include "runtime/sim/road_cache.h"
#include "tests/fuzz/targets/scratch.h"
#include "tests/fuzz/targets/targets.h"

namespace sdv::fuzz {
std::string_view cosim_scenario_text();  // generated from tests/cli/data/cosim_highway.sdv
}

using namespace sdv;

namespace {

constexpr const char* kTarget = "cosim_frame";
constexpr size_t kMaxFrames = 48;

std::shared_ptr<const ir::Program> program() {
    static const std::shared_ptr<const ir::Program> p = [] {
        diag::SourceManager sm;
        diag::DiagnosticEngine diags;
        auto c = compiler::compile_source("cosim_highway.sdv", std::string(fuzz::cosim_scenario_text()), sm, diags);
        if (!c.program) fuzz::fail(kTarget, "the embedded co-simulation scenario does not compile");
        return std::make_shared<const ir::Program>(std::move(*c.program));
    }();
    return p;
}

std::unique_ptr<cosim::Session> session(std::optional<uint64_t> seed) {
    // The road is the embedded scenario's, the same for every input: built once (the input
    // never reaches it), as the runs of a campaign share theirs.
    static const auto roads = std::make_shared<sim::RoadCache>();
    cosim::SessionOptions options;
    options.seed = seed;
    options.roads = roads;
    std::string error;
    auto s = cosim::Session::create(program(), 0, options, error);
    if (!s) fuzz::fail(kTarget, "no session: " + error);
    return s;
}

cosim::WelcomeInfo welcome_info() {
    cosim::WelcomeInfo info = cosim::welcome_info(*program(), 0);
    info.sdv_version = compiler::kCompilerVersion;
    info.scenario = "cosim_highway.sdv";
    info.scenario_sha256 = std::string(64, '0');
    return info;
}

void codec(std::string_view payload) {
    for (const auto encoding : {cosim::Encoding::binary, cosim::Encoding::json}) {
        cosim::v1::Envelope m;
        std::string error;
        if (!cosim::decode(payload, encoding, m, error)) continue;
        // JSON reads "-0" as +0 (protobuf's parser), so its fixed point is one round later.
        std::string once = cosim::encode(m, encoding);
        for (int round = encoding == cosim::Encoding::json ? 2 : 1; round > 0; --round) {
            cosim::v1::Envelope again;
            if (!cosim::decode(once, encoding, again, error)) {
                fuzz::fail(kTarget, std::string("the ") + cosim::encoding_name(encoding) +
                                        " encoding of a decoded Envelope does not decode: " + error);
            }
            std::string twice = cosim::encode(again, encoding);
            if (round == 1 && twice != once) {
                fuzz::fail(kTarget, std::string("the ") + cosim::encoding_name(encoding) +
                                        " encoding is not stable over decode and encode:\n" + once + "\n" + twice);
            }
            once = std::move(twice);
        }
    }
}

// The bytes a client sent over a connection (sdv run --cosim).
void connection(const std::string& bytes) {
    const int fd = memfd_create("sdv-fuzz-frames", MFD_CLOEXEC);
    if (fd < 0) fuzz::fail(kTarget, "memfd_create failed");
    for (size_t done = 0; done < bytes.size();) {
        const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
        if (n <= 0) fuzz::fail(kTarget, "cannot write the memfd");
        done += static_cast<size_t>(n);
    }
    ::lseek(fd, 0, SEEK_SET);
    std::vector<std::string> frames;
    cosim::FrameRead last;
    while (frames.size() < kMaxFrames) {
        std::string payload;
        last = cosim::read_frame(fd, payload, std::nullopt);
        if (last.status != cosim::FrameStatus::ok) break;
        frames.push_back(std::move(payload));
    }
    ::close(fd);
    for (const auto& f : frames) codec(f);

    const bool json = !frames.empty() && frames[0].find_first_not_of(" \t\r\n") != std::string::npos &&
                      frames[0][frames[0].find_first_not_of(" \t\r\n")] == '{';
    auto s = session(std::nullopt);
    cosim::Protocol protocol(*s, welcome_info(), json ? cosim::Encoding::json : cosim::Encoding::binary);
    for (const auto& f : frames) {
        if (protocol.closed()) break;
        (void)protocol.on_frame(f);
    }
    if (!protocol.closed()) {
        if (last.status == cosim::FrameStatus::too_large) {
            (void)protocol.fail(cosim::v1::Error::FRAME_TOO_LARGE, last.error);
        } else {
            protocol.disconnected("end of the input");
        }
    }
    (void)protocol.finish();
}

// The end of the first `max` entries of a record (direction byte, uint32 little-endian length,
// payload); all of it when it has no more entries.
size_t first_entries(const std::string& bytes, size_t max) {
    size_t at = 0;
    for (size_t k = 0; k < max; ++k) {
        if (bytes.size() - at < 5) return bytes.size();
        const auto* p = reinterpret_cast<const unsigned char*>(bytes.data() + at + 1);
        const uint64_t length = uint64_t{p[0]} | uint64_t{p[1]} << 8 | uint64_t{p[2]} << 16 | uint64_t{p[3]} << 24;
        if (length > bytes.size() - at - 5) return bytes.size();
        at += 5 + length;
    }
    return at;
}

// A record (sdv replay-cosim), as the command reads it.
void record(const std::string& bytes) {
    const std::string path = fuzz::fresh_dir(kTarget) + "/session.cosim";
    fuzz::write_file(path, std::string_view(bytes).substr(0, first_entries(bytes, kMaxFrames)));
    std::string error;
    const auto summary = cosim::summarize_record(path, error);
    if (!summary) {
        if (error.empty()) fuzz::fail(kTarget, "an unreadable record without an error message");
        return;
    }
    std::optional<uint64_t> seed;
    if (summary->welcome) seed = summary->welcome->seed();
    auto s = session(seed);
    cosim::WelcomeInfo info = welcome_info();
    if (summary->welcome) {
        info.scenario = summary->welcome->scenario();
        info.scenario_sha256 = summary->welcome->scenario_sha256();
    }
    (void)cosim::replay(path, *s, info);
}

}  // namespace

int sdv_fuzz_cosim_frame(const uint8_t* data, size_t size) {
    // protobuf logs every string field with invalid UTF-8 to stderr: noise at this rate.
    const google::protobuf::LogSilencer quiet;
    const std::string bytes(reinterpret_cast<const char*>(data), size);
    if (!bytes.empty() && bytes[0] == 'H') {
        record(bytes);
    } else {
        connection(bytes);
    }
    return 0;
}
