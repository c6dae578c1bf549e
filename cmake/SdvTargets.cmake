# Helpers that give every sdv target the same warnings and layout.

# sdv_warnings(target): the house warning set; -Werror when SDV_WERROR is on.
function(sdv_warnings target)
    target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wconversion
                                             -Wno-sign-conversion)
    # GCC 12 reports -Wrestrict false positives inside libstdc++'s std::string at -O2
    # (GCC bug 105329); they are not about our code.
    if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
        target_compile_options(${target} PRIVATE -Wno-restrict)
    endif()
    if(SDV_WERROR)
        target_compile_options(${target} PRIVATE -Werror)
    endif()
endfunction()

# sdv_library(name SOURCES ... DEPS ...): static library sdv_<name> with alias sdv::<name>.
# Headers are included as "<folder>/<file>.h" relative to the repository root.
function(sdv_library name)
    cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
    add_library(sdv_${name} STATIC ${ARG_SOURCES})
    add_library(sdv::${name} ALIAS sdv_${name})
    target_include_directories(sdv_${name} PUBLIC ${PROJECT_SOURCE_DIR})
    target_link_libraries(sdv_${name} PUBLIC ${ARG_DEPS})
    sdv_warnings(sdv_${name})
endfunction()

# sdv_unit_test(name SOURCES ... DEPS ...): a doctest executable registered with CTest, with the
# one main() of tests/unit/doctest_main.cpp (sdv_doctest_main, tests/CMakeLists.txt).
function(sdv_unit_test name)
    cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
    add_executable(${name} ${ARG_SOURCES})
    target_link_libraries(${name} PRIVATE ${ARG_DEPS} sdv_doctest_main doctest::doctest)
    sdv_test_unity(${name})
    target_compile_definitions(${name} PRIVATE
        SDV_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
        SDV_SHARED_DIR="${PROJECT_SOURCE_DIR}/../shared")
    sdv_warnings(${name})
    add_test(NAME ${name} COMMAND ${name})
endfunction()

# sdv_test_unity(target): the test sources of target compiled as one translation unit a batch
# (CMake's unity build): the headers a test file includes, and the inline code they instantiate,
# are compiled once a batch instead of once a file (the tests' share of the CI build fell from 503
# to 177 s of CPU). Each test file's code lives in a namespace named after the file, so no two
# files of a batch collide.
function(sdv_test_unity target)
    set_target_properties(${target} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE 8)
endfunction()

# sdv_foreign_host_test(test...): tests whose host program is not ours (python3 loading
# libsdv.so through ctypes). In a sanitizer build the library needs the sanitizer runtimes loaded
# first, which only the environment can do for a foreign executable; leak checking is off there
# (the interpreter's own allocations live until exit). A test script that also runs `sdv` must
# pass LD_PRELOAD on to the Python host alone (`host` in tests/cli/cosim_equivalence.sh): clang's
# executables link their own runtime and refuse a second one.
function(sdv_foreign_host_test)
    if(NOT SDV_SANITIZERS)
        return()
    endif()
    # GCC's runtimes are libasan.so and libubsan.so; clang's ASan runtime holds UBSan's too.
    set(runtimes "")
    if(CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
        if(SDV_SANITIZERS MATCHES "address")
            list(APPEND runtimes libclang_rt.asan-${CMAKE_SYSTEM_PROCESSOR}.so)
        elseif(SDV_SANITIZERS MATCHES "undefined")
            list(APPEND runtimes libclang_rt.ubsan_standalone-${CMAKE_SYSTEM_PROCESSOR}.so)
        endif()
    else()
        if(SDV_SANITIZERS MATCHES "address")
            list(APPEND runtimes libasan.so)
        endif()
        if(SDV_SANITIZERS MATCHES "undefined")
            list(APPEND runtimes libubsan.so)
        endif()
    endif()
    set(preload "")
    foreach(rt ${runtimes})
        execute_process(COMMAND ${CMAKE_CXX_COMPILER} -print-file-name=${rt}
                        OUTPUT_VARIABLE path OUTPUT_STRIP_TRAILING_WHITESPACE)
        list(APPEND preload ${path})
    endforeach()
    list(JOIN preload ":" preload)
    set_tests_properties(${ARGN} PROPERTIES ENVIRONMENT
        "LD_PRELOAD=${preload};ASAN_OPTIONS=detect_leaks=0:verify_asan_link_order=0")
endfunction()
