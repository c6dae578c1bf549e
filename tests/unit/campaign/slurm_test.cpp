// The Slurm job array of `sdv sweep --slurm` (runtime/campaign/slurm.h) without a cluster: the
// batch script's #SBATCH lines, its quoting (run with bash, every argument must arrive as
// given), the --slice argument and the exit-status files; slurm_run's clear errors (no sbatch
// on PATH, bad job) and its wait against stand-in sbatch/squeue scripts (a job not visible at
// first, tasks that leave squeue, a failed task, a task with no exit status). The real cluster
// is exercised by tests/cli/slurm_sweep.sh.
#include <doctest/doctest.h>

#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "runtime/campaign/slurm.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace slurm_test {

using namespace sdv::campaign;

namespace {

// A fresh directory under /tmp, removed at the end of the test.
struct TempDir {
    std::string path;
    TempDir() {
        char buf[] = "/tmp/sdv-slurm-test-XXXXXX";
        const char* made = ::mkdtemp(buf);
        REQUIRE(made != nullptr);
        path = made;
    }
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(path, ec);
    }
};

// Sets (or unsets, with nullopt) an environment variable for the scope.
struct EnvGuard {
    std::string name;
    std::optional<std::string> old;
    EnvGuard(const std::string& n, const std::optional<std::string>& value) : name(n) {
        if (const char* v = std::getenv(n.c_str())) old = v;
        if (value)
            ::setenv(n.c_str(), value->c_str(), 1);
        else
            ::unsetenv(n.c_str());
    }
    ~EnvGuard() {
        if (old)
            ::setenv(name.c_str(), old->c_str(), 1);
        else
            ::unsetenv(name.c_str());
    }
};

std::string read_text(const std::string& path) {
    std::ifstream in(path);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

void write_text(const std::string& path, const std::string& text, bool executable = false) {
    std::ofstream(path) << text;
    if (executable) ::chmod(path.c_str(), 0755);
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Runs `script` with bash as array task `task`; returns its stdout, sets its exit status.
std::string run_as_task(const std::string& script, int task, int& status) {
    std::string cmd = "SLURM_ARRAY_TASK_ID=" + std::to_string(task) + " bash '" + script + "' 2>&1";
    FILE* p = ::popen(cmd.c_str(), "r");
    REQUIRE(p != nullptr);
    std::string out;
    char buf[512];
    size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
    int raw = ::pclose(p);
    status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    return out;
}

SlurmJob printing_job(const std::string& dir) {
    SlurmJob job;
    job.work_dir = dir;
    // sh -c SCRIPT NAME ARGS...: prints every argument it gets, one per line, in brackets.
    job.command = {"/bin/sh", "-c", "printf '[%s]\\n' \"$@\"", "sh", "plain", "two words",
                   "it's", "say \"hi\"", "$HOME", "`id`", "back\\slash", "star*", ""};
    job.array_tasks = 4;
    return job;
}

}  // namespace

TEST_CASE("slurm_script: #SBATCH lines") {
    SlurmJob job;
    job.work_dir = "/abs/out";
    job.command = {"/abs/sdv", "sweep", "/abs/f.sdv", "-o", "/abs/out", "--jobs", "1"};
    job.array_tasks = 4;
    job.cpus_per_task = 3;
    std::string s = slurm_script(job);
    CHECK(s.rfind("#!/bin/bash\n", 0) == 0);
    CHECK(contains(s, "#SBATCH --array=0-3\n"));
    CHECK(contains(s, "#SBATCH --cpus-per-task=3\n"));
    CHECK(contains(s, "#SBATCH --job-name=sdv-sweep\n"));
    CHECK(contains(s, "#SBATCH --output=/abs/out/slurm/task-%a.log\n"));
    CHECK_FALSE(contains(s, "--partition"));
    CHECK(contains(s, "/abs/sdv sweep /abs/f.sdv -o /abs/out --jobs 1 --slice \"$id/4\"\n"));
    CHECK(contains(s, "task-$id.rc"));
    // Every #SBATCH line comes before the first command (sbatch stops reading them there).
    size_t last_sbatch = s.rfind("#SBATCH");
    size_t first_command = s.find("\nid=");
    CHECK(last_sbatch < first_command);

    job.partition = "long";
    job.array_tasks = 1;
    job.job_name = "my sweep";
    s = slurm_script(job);
    CHECK(contains(s, "#SBATCH --partition=long\n"));
    CHECK(contains(s, "#SBATCH --array=0-0\n"));
    CHECK(contains(s, "#SBATCH --job-name=\"my sweep\"\n"));
    CHECK(contains(s, "--slice \"$id/1\"\n"));

    // Log paths: blanks quoted, a literal % doubled (Slurm expands %a, %j, ... in --output).
    job.work_dir = "/abs/my 100% run/";
    s = slurm_script(job);
    CHECK(contains(s, "#SBATCH --output=\"/abs/my 100%% run/slurm/task-%a.log\"\n"));
}

TEST_CASE("slurm_script: every argument arrives as given, then --slice I/K, and the exit status is kept") {
    TempDir tmp;
    SlurmJob job = printing_job(tmp.path);
    std::filesystem::create_directories(tmp.path + "/slurm");
    std::string script = tmp.path + "/slurm/sweep.sbatch";
    write_text(script, slurm_script(job));

    int status = -1;
    std::string out = run_as_task(script, 2, status);
    CHECK(status == 0);
    CHECK(out ==
          "[plain]\n[two words]\n[it's]\n[say \"hi\"]\n[$HOME]\n[`id`]\n[back\\slash]\n[star*]\n[]\n"
          "[--slice]\n[2/4]\n");
    CHECK(read_text(tmp.path + "/slurm/task-2.rc") == "0\n");
    CHECK_FALSE(std::filesystem::exists(tmp.path + "/slurm/task-2.rc.part"));

    // A failing slice: its status is the task's status and is written down.
    job.command = {"/bin/sh", "-c", "case \"$2\" in 3/4) exit 7;; esac", "sh"};
    write_text(script, slurm_script(job));
    run_as_task(script, 3, status);
    CHECK(status == 7);
    CHECK(read_text(tmp.path + "/slurm/task-3.rc") == "7\n");
    run_as_task(script, 1, status);
    CHECK(status == 0);
    CHECK(read_text(tmp.path + "/slurm/task-1.rc") == "0\n");

    // Run outside Slurm (no task id): a clear failure, no command run.
    FILE* p = ::popen(("env -u SLURM_ARRAY_TASK_ID bash '" + script + "' 2>&1").c_str(), "r");
    REQUIRE(p != nullptr);
    char buf[512] = {};
    size_t n = std::fread(buf, 1, sizeof buf - 1, p);
    int raw = ::pclose(p);
    CHECK(WEXITSTATUS(raw) != 0);
    CHECK(contains(std::string(buf, n), "submit this script with sbatch"));
}

TEST_CASE("slurm_run: a clear error when sbatch is not on PATH") {
    TempDir tmp;
    std::filesystem::create_directories(tmp.path + "/empty");
    SlurmJob job = printing_job(tmp.path);
    int calls = 0;
    SlurmOutcome out;
    {
        EnvGuard path("PATH", tmp.path + "/empty");
        out = slurm_run(job, [&](int, int) { ++calls; });
    }
    CHECK(out.error == "sbatch not found: install slurm-wlm or run without --slurm");
    CHECK(out.job_id.empty());
    CHECK(out.failed_tasks.empty());
    CHECK(calls == 0);
    // Nothing was written either.
    CHECK_FALSE(std::filesystem::exists(tmp.path + "/slurm/sweep.sbatch"));
}

TEST_CASE("slurm_run: a job it cannot describe to Slurm is an error, not a crash") {
    SlurmJob job;
    job.command = {"/bin/true"};
    job.work_dir = "relative/dir";
    CHECK(contains(slurm_run(job, nullptr).error, "absolute path"));
    job.work_dir = "/tmp/a\"b";
    CHECK(contains(slurm_run(job, nullptr).error, "double quote"));
    job.work_dir = "/tmp/x";
    job.array_tasks = 0;
    CHECK(contains(slurm_run(job, nullptr).error, "at least 1"));
    job.array_tasks = 2;
    job.command.clear();
    CHECK(contains(slurm_run(job, nullptr).error, "no command"));
    job.command = {"sdv", "sweep"};
    CHECK(contains(slurm_run(job, nullptr).error, "absolute path"));
}

TEST_CASE("slurm_run: waits through squeue, reads each task's exit status") {
    TempDir tmp;
    const std::string bin = tmp.path + "/bin";
    std::filesystem::create_directories(bin);
    // sbatch: runs tasks 0 and 2 of the script at once (task 1 "is killed": no exit status),
    // prints "JOBID;CLUSTER" as --parsable does.
    write_text(bin + "/sbatch",
               "#!/bin/sh\n"
               "[ \"$1\" = --parsable ] || { echo \"unexpected $1\" >&2; exit 1; }\n"
               "for id in 0 2; do SLURM_ARRAY_TASK_ID=$id bash \"$2\" >/dev/null 2>&1; done\n"
               "echo '77;local'\n",
               true);
    // squeue: not visible at first, then tasks leave it; counts its calls in a file.
    write_text(bin + "/squeue",
               "#!/bin/sh\n"
               "f=" + tmp.path + "/calls; n=$(($(cat \"$f\" 2>/dev/null || echo 0) + 1)); echo $n > \"$f\"\n"
               "echo \"$*\" > " + tmp.path + "/args\n"
               "case $n in\n"
               "1) echo 'slurm_load_jobs error: Invalid job id specified' >&2; exit 1;;\n"
               "2) printf '77_0 COMPLETED\\n77_1 RUNNING\\n77_2 PENDING\\n';;\n"
               "3) printf '77_0 COMPLETED\\n77_1 RUNNING\\n77_2 COMPLETING\\n';;\n"
               "4) printf '77_0 COMPLETED\\n';;\n"
               "*) echo 'slurm_load_jobs error: Invalid job id specified' >&2; exit 1;;\n"
               "esac\n",
               true);
    SlurmJob job;
    job.work_dir = tmp.path + "/out";
    job.command = {"/bin/sh", "-c", "case \"$2\" in 2/3) echo boom; exit 5;; esac", "sh"};
    job.array_tasks = 3;
    // A stale exit status from an earlier run must not count.
    std::filesystem::create_directories(job.work_dir + "/slurm");
    write_text(job.work_dir + "/slurm/task-1.rc", "0\n");

    std::vector<std::pair<int, int>> progress;
    SlurmOutcome out;
    {
        EnvGuard path("PATH", bin + ":/usr/bin:/bin");
        EnvGuard conf("SLURM_CONF", std::nullopt);
        out = slurm_run(job, [&](int done, int total) { progress.emplace_back(done, total); });
    }
    CHECK(out.job_id == "77");
    CHECK(out.failed_tasks == std::vector<int>{1, 2});
    CHECK(out.error == "task 1 failed (no exit status: cancelled, killed or out of time): see " + job.work_dir +
                           "/slurm/task-1.log (2 of 3 tasks failed)");
    CHECK(progress == std::vector<std::pair<int, int>>{{1, 3}, {2, 3}, {3, 3}});
    CHECK(read_text(tmp.path + "/calls") == "4\n");
    CHECK(read_text(tmp.path + "/args") == "-h -r -t all -j 77 -o %i %T\n");
    CHECK(read_text(job.work_dir + "/slurm/task-2.rc") == "5\n");
    CHECK(contains(read_text(job.work_dir + "/slurm/sweep.sbatch"), "#SBATCH --array=0-2\n"));
}

TEST_CASE("slurm_run: sbatch's own error is the message") {
    TempDir tmp;
    const std::string bin = tmp.path + "/bin";
    std::filesystem::create_directories(bin);
    write_text(bin + "/sbatch",
               "#!/bin/sh\necho 'sbatch: error: invalid partition specified: nope' >&2\n"
               "echo 'sbatch: error: Batch job submission failed: Invalid partition name specified' >&2\nexit 1\n",
               true);
    write_text(bin + "/squeue", "#!/bin/sh\nexit 1\n", true);
    SlurmJob job;
    job.work_dir = tmp.path + "/out";
    job.command = {"/bin/true"};
    job.partition = "nope";
    SlurmOutcome out;
    {
        EnvGuard path("PATH", bin);
        EnvGuard conf("SLURM_CONF", std::nullopt);
        out = slurm_run(job, nullptr);
    }
    CHECK(out.error ==
          "sbatch failed: sbatch: error: invalid partition specified: nope; sbatch: error: Batch job submission "
          "failed: Invalid partition name specified");
    CHECK(out.job_id.empty());
}

}  // namespace slurm_test
