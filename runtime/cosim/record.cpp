// Record entries reuse the frame reader and writer (framing.h) on a file descriptor, so a record
// is read with the same limits and checks as the wire.
#include "runtime/cosim/record.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <nlohmann/json.hpp>

namespace sdv::cosim {

std::unique_ptr<RecordWriter> RecordWriter::create(const std::string& path,
                                                   const RecordHeader& header, std::string& error) {
    std::unique_ptr<RecordWriter> w(new RecordWriter());
    w->path_ = path;
    w->file_ = Socket(::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644));
    if (!w->file_.valid()) {
        error = "cannot write the record '" + path + "': " + std::strerror(errno);
        return nullptr;
    }
    nlohmann::ordered_json h;
    h["format"] = "sdv-cosim-record";
    h["version"] = header.version;
    h["encoding"] = encoding_name(header.encoding);
    h["scenario"] = header.scenario;
    h["scenario_name"] = header.scenario_name;
    h["sdv_version"] = header.sdv_version;
    if (auto e = w->append(Direction::header, h.dump()); !e.empty()) {
        error = e;
        return nullptr;
    }
    return w;
}

std::string RecordWriter::append(Direction direction, std::string_view payload) {
    if (payload.size() > kMaxFramePayload)
        return "cannot record a frame of " + std::to_string(payload.size()) + " bytes";
    std::string entry(1, static_cast<char>(direction));
    entry += frame_prefix(static_cast<uint32_t>(payload.size()));
    entry.append(payload);
    if (auto e = write_all(file_.fd(), entry, std::nullopt); !e.empty()) {
        return "cannot write the record '" + path_ + "': " + e;
    }
    return "";
}

std::unique_ptr<RecordReader> RecordReader::open(const std::string& path, std::string& error) {
    std::unique_ptr<RecordReader> r(new RecordReader());
    r->path_ = path;
    r->file_ = Socket(::open(path.c_str(), O_RDONLY | O_CLOEXEC));
    if (!r->file_.valid()) {
        error = "cannot read '" + path + "': " + std::strerror(errno);
        return nullptr;
    }
    Direction d;
    std::string payload;
    std::string e;
    if (r->next(d, payload, e) != Next::frame || d != Direction::header) {
        error = "'" + path + "' is no sdv-cosim record (it must start with a header entry)" +
                (e.empty() ? "" : ": " + e);
        return nullptr;
    }
    const auto h = nlohmann::json::parse(payload, nullptr, false);
    if (!h.is_object() || h.value("format", "") != "sdv-cosim-record" || !h.contains("version") ||
        !h["version"].is_number_integer()) {
        error = "'" + path + "' is no sdv-cosim record (bad header)";
        return nullptr;
    }
    r->header_.version = h["version"].get<int>();
    if (r->header_.version != 1) {
        error = "'" + path + "' is a record of version " + std::to_string(r->header_.version) +
                "; this sdv reads version 1";
        return nullptr;
    }
    const auto enc = parse_encoding(h.value("encoding", ""));
    if (!enc) {
        error = "'" + path + "': unknown encoding in the record's header";
        return nullptr;
    }
    r->header_.encoding = *enc;
    r->header_.scenario = h.value("scenario", "");
    r->header_.scenario_name = h.value("scenario_name", "");
    r->header_.sdv_version = h.value("sdv_version", "");
    return r;
}

RecordReader::Next RecordReader::next(Direction& direction, std::string& payload,
                                      std::string& error) {
    char marker = 0;
    bool timed_out = false;
    const long long got = read_exact(file_.fd(), &marker, 1, std::nullopt, error, timed_out);
    if (got < 0) return Next::error;
    if (got == 0) return Next::end;
    ++entries_;
    if (marker != 'H' && marker != 'C' && marker != 'S') {
        error = "entry " + std::to_string(entries_) + " has no direction marker (byte " +
                std::to_string(static_cast<unsigned char>(marker)) + ")";
        return Next::error;
    }
    if ((marker == 'H') != (entries_ == 1)) {
        error = "entry " + std::to_string(entries_) +
                ": the header must be the first entry and only it";
        return Next::error;
    }
    direction = static_cast<Direction>(marker);
    const FrameRead f = read_frame(file_.fd(), payload, std::nullopt);
    if (f.status != FrameStatus::ok) {
        error = "entry " + std::to_string(entries_) + ": " +
                (f.status == FrameStatus::eof ? "the record ends after its marker" : f.error);
        return Next::error;
    }
    return Next::frame;
}

}  // namespace sdv::cosim
