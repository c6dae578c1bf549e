// SHA-256 (FIPS 180-4) of a byte string, for Welcome.scenario_sha256: a client can tell which
// scenario file a session ran without trusting its path. A few dozen lines rather than a crypto
// library for one digest of a small file per session.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>

namespace sdv::cosim {

// Incremental: update() any number of times, then digest() once.
class Sha256 {
  public:
    Sha256();
    void update(std::string_view bytes);
    std::array<uint8_t, 32> digest();

  private:
    void block(const uint8_t* p);
    std::array<uint32_t, 8> h_;
    std::array<uint8_t, 64> buffer_{};
    size_t buffered_ = 0;
    uint64_t length_ = 0;  // bytes so far
};

// The digest of `bytes` as 64 lower-case hex digits.
std::string sha256_hex(std::string_view bytes);

}  // namespace sdv::cosim
