// The standard tree library, embedded in the binary at build time (see embed.cmake).
// Files are addressed as "std/<file>.sdv", exactly as written in an import.
#pragma once

#include <span>
#include <string_view>

namespace sdv::stdlib {

struct File {
    std::string_view path;      // "std/drive.sdv"
    std::string_view contents;
};

std::span<const File> files();

// The file for an import path, or nullptr.
const File* find(std::string_view path);

}  // namespace sdv::stdlib
