#include "runtime/cosim/sha256.h"

#include <doctest/doctest.h>

#include <string>

// This file's tests and helpers, apart from the other files of its unity batch.
namespace sha256_test {

using sdv::cosim::Sha256;
using sdv::cosim::sha256_hex;

TEST_CASE("sha256: FIPS 180-4 and NIST test vectors") {
    CHECK(sha256_hex("") == "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
    CHECK(sha256_hex("abc") == "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    CHECK(sha256_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq") ==
          "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
    CHECK(sha256_hex("abcdefghbcdefghicdefghijdefghijkefghijklfghijklmghijklmnhijklmnoijklmnopjklmn"
                     "opqklmnopqrlmnopqrsmnopqrstnopqrstu") ==
          "cf5b16a778af8380036ce59e7b0492370b249b11e8f07a51afac45037afee9d1");
    CHECK(sha256_hex(std::string(1000000, 'a')) ==
          "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST_CASE("sha256: block boundaries (55, 56, 63, 64, 65 bytes) and incremental updates agree") {
    // 55 bytes is the longest message whose padding fits one block; 56 needs two.
    CHECK(sha256_hex(std::string(55, 'a')) ==
          "9f4390f8d30c2dd92ec9f095b65e2b9ae9b0a925a5258e241c9f1e910f734318");
    CHECK(sha256_hex(std::string(56, 'a')) ==
          "b35439a4ac6f0948b6d6f9e3c6af0f5f590ce20f1bde7090ef7970686ec6738a");
    CHECK(sha256_hex(std::string(64, 'a')) ==
          "ffe054fe7ae0cb6dc65c3af9b61d5209f439851db43d0ba5997337df154668eb");
    for (size_t n : {0, 1, 55, 56, 63, 64, 65, 127, 128, 1000}) {
        std::string text;
        for (size_t i = 0; i < n; ++i) text += static_cast<char>('a' + i % 26);
        for (size_t cut = 0; cut <= n; cut += 7) {
            Sha256 s;
            s.update(std::string_view(text).substr(0, cut));
            s.update(std::string_view(text).substr(cut));
            std::string hex;
            for (uint8_t b : s.digest()) {
                static constexpr char kHex[] = "0123456789abcdef";
                hex += kHex[b >> 4];
                hex += kHex[b & 15];
            }
            CHECK(hex == sha256_hex(text));
        }
    }
}

}  // namespace sha256_test
