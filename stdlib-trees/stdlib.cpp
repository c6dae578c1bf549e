// Lookup in the embedded standard tree library.
#include "stdlib-trees/stdlib.h"

namespace sdv::stdlib {

const File* find(std::string_view path) {
    for (const File& f : files()) {
        if (f.path == path) return &f;
    }
    return nullptr;
}

}  // namespace sdv::stdlib
