// The libFuzzer entry point of one target, chosen at compile time: fuzz_NAME is this file
// built with -DSDV_FUZZ_TARGET=NAME, calling sdv_fuzz_NAME (targets/NAME.cpp).
#include <cstddef>
#include <cstdint>

#include "tests/fuzz/targets/targets.h"

#ifndef SDV_FUZZ_TARGET
#error "build with -DSDV_FUZZ_TARGET=<name of a target in targets/targets.h>"
#endif
#define SDV_FUZZ_CAT2(a, b) a##b
#define SDV_FUZZ_CAT(a, b) SDV_FUZZ_CAT2(a, b)

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    return SDV_FUZZ_CAT(sdv_fuzz_, SDV_FUZZ_TARGET)(data, size);
}
