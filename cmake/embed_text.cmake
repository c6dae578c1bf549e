# Writes one text file into a C++ source as a byte array with an accessor (run by CMake -P):
#   cmake -DIN=file -DOUT=out.cpp -DNAMESPACE=sdv::io -DFUNCTION=viewer_template -P embed_text.cmake
# The file is named relative to the source tree, so the output is the same wherever the tree is.
file(RELATIVE_PATH name "${CMAKE_CURRENT_LIST_DIR}/.." "${IN}")
file(READ ${IN} hex HEX)
string(REGEX REPLACE "([0-9a-f][0-9a-f])" "0x\\1," hex "${hex}")
file(WRITE ${OUT} "// Generated from ${name} by cmake/embed_text.cmake; do not edit.\n#include <string_view>\n\nnamespace ${NAMESPACE} {\nnamespace {\nconst unsigned char kData[] = {${hex} 0};\n}  // namespace\n\nstd::string_view ${FUNCTION}() { return {reinterpret_cast<const char*>(kData), sizeof(kData) - 1}; }\n\n}  // namespace ${NAMESPACE}\n")
