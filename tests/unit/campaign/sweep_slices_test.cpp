// The slices of one sweep run at the same time into the same directory, as the array tasks of
// `sdv sweep --slurm` do on a cluster: every slice must start (they all write the campaign's
// manifest at once), and the gathered rows must be the whole campaign, each variant once.
#include <doctest/doctest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "runtime/campaign/sweep.h"
#include "tests/unit/io/compile_text.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace sweep_slices_test {

using namespace sdv;

namespace {

const char* kScenario = R"(
import "std/drive.sdv"
road r {
    lanes 1 forward
    straight 200 m
}
scenario s {
    road r
    timeout 1 s
    vehicle v: sdv {
        start lane 1 at 10 m
        speed 5 m/s
        tree std.drive(speed = 5 m/s)
    }
    vary {
        v.speed in 2 m/s .. 9 m/s count 16
        sample grid
    }
}
)";

std::string temp_dir() {
    char buf[] = "/tmp/sdv-sweep-slices-XXXXXX";
    const char* made = ::mkdtemp(buf);
    REQUIRE(made != nullptr);
    return made;
}

}  // namespace

TEST_CASE("slices started at the same moment in one directory all run, and gather the whole campaign") {
    const auto program = test::compile_text(kScenario);
    REQUIRE(program);
    constexpr int kSlices = 8;
    // A race shows only sometimes: start the slices together several times over.
    for (int round = 0; round < 16; ++round) {
        const std::string dir = temp_dir();
        std::vector<pid_t> children;
        // The children wait at a barrier (a pipe the parent closes) so they start together.
        int barrier[2];
        REQUIRE(::pipe(barrier) == 0);
        for (int slice = 0; slice < kSlices; ++slice) {
            const pid_t pid = ::fork();
            REQUIRE(pid >= 0);
            if (pid == 0) {
                ::close(barrier[1]);
                char c;
                while (::read(barrier[0], &c, 1) > 0) {
                }
                campaign::SweepOptions o;
                o.dir = dir;
                o.slice = slice;
                o.slices = kSlices;
                const auto out = campaign::run_sweep(*program, 0, o);
                ::_exit(out.error.empty() && out.ran == 2 ? 0 : 1);
            }
            children.push_back(pid);
        }
        ::close(barrier[0]);
        ::close(barrier[1]);
        for (const pid_t pid : children) {
            int status = 0;
            REQUIRE(::waitpid(pid, &status, 0) == pid);
            CHECK_MESSAGE((WIFEXITED(status) && WEXITSTATUS(status) == 0), "round " << round);
        }
        campaign::Results results;
        CHECK(campaign::gather(*program, 0, dir, results) == "");
        REQUIRE(results.rows.size() == 16);
        for (size_t i = 0; i < results.rows.size(); ++i) CHECK(results.rows[i].variant == static_cast<int64_t>(i));
        // Nothing is left behind but the manifest and the slice files.
        for (const auto& entry : std::filesystem::directory_iterator(dir + "/rows"))
            CHECK_MESSAGE(entry.path().extension() != ".part", entry.path().string());
        std::error_code ec;
        std::filesystem::remove_all(dir, ec);
    }
}

}  // namespace sweep_slices_test
