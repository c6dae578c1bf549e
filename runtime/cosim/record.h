// The record of a co-simulation session (`--cosim-record FILE`, docs/cosim.md "Record and
// replay"): every frame received and sent, in order, with the wire's own framing behind a
// one-byte direction marker, so that replay can pick out the client's frames:
//
//   entry  = direction (1 byte) + uint32 little-endian length + payload
//   'H'    the header, first and once: a JSON object {"format":"sdv-cosim-record","version":1,
//          "encoding":"binary"|"json","scenario":ABSOLUTE PATH,"scenario_name":NAME,
//          "sdv_version":...}
//   'C'    a frame received from the client, payload exactly as received (even unparseable)
//   'S'    a frame sent by sdv, payload exactly as sent
//
// Each entry is written with one write() as it passes, so a record of a session that was killed
// ends at most with one incomplete entry. The file is created (truncated) when the server starts.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "runtime/cosim/codec.h"
#include "runtime/cosim/transport.h"

namespace sdv::cosim {

struct RecordHeader {
    int version = 1;
    Encoding encoding = Encoding::binary;
    std::string scenario;       // absolute path of the scenario file
    std::string scenario_name;  // which scenario of the file
    std::string sdv_version;
};

enum class Direction : char { header = 'H', client = 'C', server = 'S' };

class RecordWriter {
  public:
    // Creates the file and writes the header; nullptr with `error` on failure.
    static std::unique_ptr<RecordWriter> create(const std::string& path, const RecordHeader& header,
                                                std::string& error);
    // Appends one entry; an error message or "".
    std::string append(Direction direction, std::string_view payload);
    const std::string& path() const { return path_; }

  private:
    RecordWriter() = default;
    Socket file_;  // an owned descriptor (not necessarily a socket)
    std::string path_;
};

class RecordReader {
  public:
    // Opens a record and reads its header; nullptr with `error` when it is no record.
    static std::unique_ptr<RecordReader> open(const std::string& path, std::string& error);
    const RecordHeader& header() const { return header_; }

    enum class Next { frame, end, error };
    // The next client or server frame. `end` at the end of the file; `error` (with `error`) for
    // an incomplete last entry or bytes that are no entry.
    Next next(Direction& direction, std::string& payload, std::string& error);

  private:
    RecordReader() = default;
    Socket file_;
    std::string path_;
    RecordHeader header_;
    uint64_t entries_ = 0;
};

}  // namespace sdv::cosim
