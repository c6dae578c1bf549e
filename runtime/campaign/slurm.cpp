// `sdv sweep --slurm`: writes the job array's batch script, submits it with sbatch, waits by
// polling squeue and reads each array task's exit-status file. Slurm's commands run as child
// processes (posix_spawn, stdout and stderr through pipes, this process's environment), each
// bounded in time; nothing here throws.
#include "runtime/campaign/slurm.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <set>
#include <thread>

extern char** environ;

namespace sdv::campaign {
namespace {

constexpr auto poll_interval = std::chrono::milliseconds(500);
// squeue failing (job not visible yet, controller busy or restarting) is tolerated until it has
// failed for this long and this many times in a row (each failing call can take seconds).
constexpr auto squeue_failure_window = std::chrono::seconds(120);
constexpr int min_squeue_failures = 10;
// A job never listed (squeue says "Invalid job id": it may have ended and been purged before
// the first poll) counts as finished after this many polls.
constexpr int unseen_grace_polls = 10;
// A missing .rc file is looked for again this many times (0.5 s apart) in case the shared file
// system shows it late.
constexpr int rc_retries = 6;
// Seconds a single sbatch / squeue may take before it is killed.
constexpr int sbatch_timeout_s = 300;
constexpr int squeue_timeout_s = 120;

std::string sys_error(const std::string& what, int err) { return what + ": " + std::strerror(err); }

// POSIX single quotes, only where the word needs them (so the script stays readable).
std::string shell_quote(const std::string& s) {
    bool plain = !s.empty();
    for (char c : s) {
        bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                  (c != '\0' && std::strchr("_-+./:=,@%", c) != nullptr);
        if (!ok) {
            plain = false;
            break;
        }
    }
    if (plain) return s;
    std::string out = "'";
    for (char c : s) {
        if (c == '\'')
            out += "'\\''";
        else
            out += c;
    }
    return out + "'";
}

// A value on an #SBATCH line: sbatch splits those lines at blanks but keeps double-quoted text
// together (checked with Slurm 22.05). validate() rejects the characters this cannot carry.
std::string sbatch_value(const std::string& s) {
    bool blank = s.empty() || s.find_first_of(" \t'#") != std::string::npos;
    return blank ? "\"" + s + "\"" : s;
}

// Slurm expands %a, %j, ... in --output; a literal % is %%.
std::string pattern_escape(const std::string& s) {
    std::string out;
    for (char c : s) {
        out += c;
        if (c == '%') out += '%';
    }
    return out;
}

std::string slurm_dir(const SlurmJob& job) {
    std::string dir = job.work_dir;
    while (dir.size() > 1 && dir.back() == '/') dir.pop_back();
    return dir == "/" ? "/slurm" : dir + "/slurm";
}

std::string task_file(const SlurmJob& job, int task, const char* ext) {
    return slurm_dir(job) + "/task-" + std::to_string(task) + ext;
}

// Text fit for a one-line message: lines joined with "; ", trimmed, capped.
std::string one_line(const std::string& text) {
    std::string out;
    size_t start = 0;
    while (start <= text.size()) {
        size_t end = text.find('\n', start);
        if (end == std::string::npos) end = text.size();
        std::string line = text.substr(start, end - start);
        while (!line.empty() && (line.back() == '\r' || line.back() == ' ' || line.back() == '\t'))
            line.pop_back();
        size_t first = line.find_first_not_of(" \t");
        if (first != std::string::npos) {
            if (!out.empty()) out += "; ";
            out += line.substr(first);
        }
        start = end + 1;
    }
    if (out.size() > 400) out = out.substr(0, 400) + "...";
    return out;
}

bool has_char_of(const std::string& s, const char* chars) { return s.find_first_of(chars) != std::string::npos; }

std::string validate(const SlurmJob& job) {
    if (job.work_dir.empty() || job.work_dir[0] != '/')
        return "the Slurm work directory must be an absolute path (got '" + job.work_dir + "')";
    // Double quotes and line breaks cannot be carried by an #SBATCH line; a backslash would turn
    // off the %a in the log file names.
    if (has_char_of(job.work_dir, "\"\\\n\r"))
        return "the Slurm work directory '" + job.work_dir +
               "' contains a double quote, backslash or line break, which Slurm's #SBATCH lines cannot carry";
    if (has_char_of(job.partition, "\"\\\n\r \t"))
        return "invalid Slurm partition name '" + job.partition + "'";
    if (has_char_of(job.job_name, "\"\\\n\r"))
        return "invalid Slurm job name '" + job.job_name + "' (double quote, backslash or line break)";
    if (job.command.empty()) return "no command to run in the Slurm array tasks";
    if (job.command[0].empty() || job.command[0][0] != '/')
        return "the Slurm task command must start with an absolute path (got '" + job.command[0] + "')";
    for (const auto& arg : job.command)
        if (arg.find('\0') != std::string::npos) return "a Slurm task argument contains a NUL byte";
    if (job.array_tasks < 1) return "the number of array tasks must be at least 1 (got " + std::to_string(job.array_tasks) + ")";
    if (job.cpus_per_task < 1)
        return "CPUs per array task must be at least 1 (got " + std::to_string(job.cpus_per_task) + ")";
    if (job.max_polls < 1) return "max_polls must be at least 1";
    return "";
}

// The executable `name` on PATH, or "".
std::string find_in_path(const std::string& name) {
    const char* path = std::getenv("PATH");
    if (!path) return "";
    std::string all = path;
    size_t start = 0;
    while (start <= all.size()) {
        size_t end = all.find(':', start);
        if (end == std::string::npos) end = all.size();
        std::string dir = all.substr(start, end - start);
        if (dir.empty()) dir = ".";
        std::string candidate = dir + "/" + name;
        struct stat st {};
        if (::stat(candidate.c_str(), &st) == 0 && S_ISREG(st.st_mode) && ::access(candidate.c_str(), X_OK) == 0)
            return candidate;
        start = end + 1;
    }
    return "";
}

struct Captured {
    bool spawned = false;
    std::string failure;  // could not run it, or it timed out
    int status = -1;      // exit status (128 + signal when killed by one)
    std::string out, err;
};

void close_fd(int& fd) {
    if (fd >= 0) ::close(fd);
    fd = -1;
}

// Runs `exe` with `args` (args[0] is argv[0]), stdin from /dev/null, capturing stdout and
// stderr; kills it after `timeout_s` seconds.
Captured run_capture(const std::string& exe, const std::vector<std::string>& args, int timeout_s) {
    Captured result;
    int out_pipe[2] = {-1, -1}, err_pipe[2] = {-1, -1};
    if (::pipe2(out_pipe, O_CLOEXEC) != 0 || ::pipe2(err_pipe, O_CLOEXEC) != 0) {
        result.failure = sys_error("cannot create a pipe", errno);
        for (int* fd : {&out_pipe[0], &out_pipe[1], &err_pipe[0], &err_pipe[1]}) close_fd(*fd);
        return result;
    }
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_adddup2(&actions, out_pipe[1], 1);
    posix_spawn_file_actions_adddup2(&actions, err_pipe[1], 2);
    std::vector<std::string> storage = args;
    std::vector<char*> argv;
    for (auto& a : storage) argv.push_back(a.data());
    argv.push_back(nullptr);
    pid_t pid = -1;
    int rc = ::posix_spawn(&pid, exe.c_str(), &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    close_fd(out_pipe[1]);
    close_fd(err_pipe[1]);
    if (rc != 0) {
        result.failure = sys_error("cannot run " + exe, rc);
        close_fd(out_pipe[0]);
        close_fd(err_pipe[0]);
        return result;
    }
    result.spawned = true;

    auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(timeout_s);
    int fds[2] = {out_pipe[0], err_pipe[0]};
    std::string* sinks[2] = {&result.out, &result.err};
    bool timed_out = false;
    while (fds[0] >= 0 || fds[1] >= 0) {
        auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
        if (left.count() <= 0) {
            timed_out = true;
            break;
        }
        pollfd pfds[2];
        nfds_t n = 0;
        int which[2];
        for (int i = 0; i < 2; ++i) {
            if (fds[i] < 0) continue;
            pfds[n] = {fds[i], POLLIN, 0};
            which[n] = i;
            ++n;
        }
        int ready = ::poll(pfds, n, static_cast<int>(std::min<long long>(left.count(), 1000)));
        if (ready < 0) {
            if (errno == EINTR) continue;
            result.failure = sys_error("poll", errno);
            timed_out = true;  // kill and reap it below
            break;
        }
        for (nfds_t k = 0; k < n; ++k) {
            if (pfds[k].revents == 0) continue;
            int i = which[k];
            char buf[4096];
            ssize_t got = ::read(fds[i], buf, sizeof buf);
            if (got > 0)
                sinks[i]->append(buf, static_cast<size_t>(got));
            else if (got == 0 || (errno != EINTR && errno != EAGAIN))
                close_fd(fds[i]);
        }
    }
    close_fd(fds[0]);
    close_fd(fds[1]);
    if (timed_out) ::kill(pid, SIGKILL);
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0) {
        if (errno != EINTR) {
            if (result.failure.empty()) result.failure = sys_error("waitpid", errno);
            return result;
        }
    }
    if (timed_out) {
        if (result.failure.empty())
            result.failure = args[0] + " did not finish within " + std::to_string(timeout_s) + " s";
        return result;
    }
    result.status = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    return result;
}

std::string write_file(const std::string& path, const std::string& text) {
    std::string part = path + ".part";
    FILE* f = std::fopen(part.c_str(), "w");
    if (!f) return sys_error("cannot write " + part, errno);
    bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size();
    int err = errno;
    if (std::fclose(f) != 0 && ok) {
        ok = false;
        err = errno;
    }
    if (!ok) {
        ::unlink(part.c_str());
        return sys_error("cannot write " + part, err);
    }
    if (::rename(part.c_str(), path.c_str()) != 0) {
        err = errno;
        ::unlink(part.c_str());
        return sys_error("cannot rename " + part + " to " + path, err);
    }
    return "";
}

// A task's exit status from its .rc file: false when the file is missing or unreadable.
bool read_rc(const std::string& path, int& status) {
    FILE* f = std::fopen(path.c_str(), "r");
    if (!f) return false;
    char buf[64] = {};
    size_t got = std::fread(buf, 1, sizeof buf - 1, f);
    std::fclose(f);
    const char* begin = buf;
    const char* end = buf + got;
    while (end > begin && (end[-1] == '\n' || end[-1] == ' ' || end[-1] == '\r')) --end;
    auto [ptr, ec] = std::from_chars(begin, end, status);
    return ec == std::errc() && ptr == end && begin != end;
}

// squeue states (%T) of a task that will not run any more (COMPLETING: the script has exited).
bool finished_state(const std::string& state) {
    static const std::set<std::string> finished = {
        "COMPLETED", "COMPLETING", "FAILED", "CANCELLED", "TIMEOUT", "NODE_FAIL", "OUT_OF_MEMORY",
        "PREEMPTED", "BOOT_FAIL", "DEADLINE", "SPECIAL_EXIT", "REVOKED"};
    return finished.count(state) > 0;
}

enum class TaskState { unknown, active, finished };

// Updates `tasks` from the lines "JOBID_TASK STATE" of `squeue -r -t all -o "%i %T"`: a task
// listed takes its state; one seen before and no longer listed has been purged after it ended.
// Returns the number of tasks listed.
int update_tasks(const std::string& out, const std::string& job_id, std::vector<TaskState>& tasks) {
    std::vector<bool> listed(tasks.size(), false);
    int count = 0;
    const std::string prefix = job_id + "_";
    size_t start = 0;
    while (start < out.size()) {
        size_t end = out.find('\n', start);
        if (end == std::string::npos) end = out.size();
        std::string line = out.substr(start, end - start);
        start = end + 1;
        size_t sp = line.find(' ');
        if (sp == std::string::npos || line.compare(0, prefix.size(), prefix) != 0) continue;
        int task = -1;
        const char* first = line.data() + prefix.size();
        const char* last = line.data() + sp;
        auto [ptr, ec] = std::from_chars(first, last, task);
        if (ec != std::errc() || ptr != last || task < 0 || task >= static_cast<int>(tasks.size())) continue;
        size_t from = line.find_first_not_of(' ', sp);
        std::string state = from == std::string::npos ? "" : line.substr(from);
        while (!state.empty() && (state.back() == ' ' || state.back() == '\r')) state.pop_back();
        auto i = static_cast<size_t>(task);
        if (!listed[i]) ++count;
        listed[i] = true;
        tasks[i] = finished_state(state) ? TaskState::finished : TaskState::active;
    }
    for (size_t i = 0; i < tasks.size(); ++i)
        if (!listed[i] && tasks[i] == TaskState::active) tasks[i] = TaskState::finished;
    return count;
}

}  // namespace

std::string slurm_script(const SlurmJob& job) {
    const int k = job.array_tasks;
    const std::string dir = slurm_dir(job);
    std::string s;
    s += "#!/bin/bash\n";
    s += "# sdv sweep --slurm: array task I of this job runs slice I/" + std::to_string(k) +
         " of the sweep and writes its exit\n";
    s += "# status to task-I.rc next to this script (written by sdv; it can be resubmitted with sbatch).\n";
    s += "#SBATCH --job-name=" + sbatch_value(job.job_name) + "\n";
    s += "#SBATCH --array=0-" + std::to_string(k - 1) + "\n";
    if (!job.partition.empty()) s += "#SBATCH --partition=" + sbatch_value(job.partition) + "\n";
    s += "#SBATCH --ntasks=1\n";
    s += "#SBATCH --cpus-per-task=" + std::to_string(job.cpus_per_task) + "\n";
    s += "#SBATCH --output=" + sbatch_value(pattern_escape(dir) + "/task-%a.log") + "\n";
    s += "#SBATCH --chdir=" + sbatch_value(job.work_dir) + "\n";
    s += "id=${SLURM_ARRAY_TASK_ID:?submit this script with sbatch: it is a job array}\n";
    std::string line;
    for (const auto& arg : job.command) line += shell_quote(arg) + " ";
    line += "--slice \"$id/" + std::to_string(k) + "\"\n";
    s += line;
    s += "rc=$?\n";
    s += "rc_file=" + shell_quote(dir) + "/task-$id.rc\n";
    s += "printf '%s\\n' \"$rc\" > \"$rc_file.part\" && mv -f \"$rc_file.part\" \"$rc_file\"\n";
    s += "exit \"$rc\"\n";
    return s;
}

SlurmOutcome slurm_run(const SlurmJob& job, const std::function<void(int done, int total)>& progress) {
    SlurmOutcome outcome;
    outcome.error = validate(job);
    if (!outcome.error.empty()) return outcome;
    const int k = job.array_tasks;

    std::string sbatch = find_in_path("sbatch");
    if (sbatch.empty()) {
        outcome.error = "sbatch not found: install slurm-wlm or run without --slurm";
        return outcome;
    }
    std::string squeue = find_in_path("squeue");
    if (squeue.empty()) {
        outcome.error = "squeue not found: install slurm-wlm or run without --slurm";
        return outcome;
    }
    // Slurm's commands retry a missing configuration file for a minute before they fail.
    if (const char* conf = std::getenv("SLURM_CONF"); conf && *conf && ::access(conf, R_OK) != 0) {
        outcome.error = sys_error(std::string("SLURM_CONF names ") + conf + ", which cannot be read", errno);
        return outcome;
    }

    // The script, and no exit-status file left from an earlier submission.
    const std::string dir = slurm_dir(job);
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) {
        outcome.error = "cannot create " + dir + ": " + ec.message();
        return outcome;
    }
    for (int t = 0; t < k; ++t)
        for (const char* ext : {".rc", ".rc.part"}) {
            std::string path = task_file(job, t, ext);
            if (::unlink(path.c_str()) != 0 && errno != ENOENT) {
                outcome.error = sys_error("cannot remove " + path, errno);
                return outcome;
            }
        }
    const std::string script = dir + "/sweep.sbatch";
    outcome.error = write_file(script, slurm_script(job));
    if (!outcome.error.empty()) return outcome;

    // Submit.
    Captured sub = run_capture(sbatch, {"sbatch", "--parsable", script}, sbatch_timeout_s);
    if (!sub.failure.empty()) {
        outcome.error = "sbatch failed: " + sub.failure;
        return outcome;
    }
    if (sub.status != 0) {
        std::string why = one_line(sub.err);
        outcome.error = "sbatch failed: " + (why.empty() ? "exit status " + std::to_string(sub.status) : why);
        return outcome;
    }
    // --parsable prints "JOBID" or "JOBID;CLUSTER".
    std::string id = one_line(sub.out);
    id = id.substr(0, id.find(';'));
    if (id.empty() || !std::all_of(id.begin(), id.end(), [](char c) { return c >= '0' && c <= '9'; })) {
        outcome.error = "sbatch printed no job id (stdout: '" + one_line(sub.out) + "')";
        return outcome;
    }
    outcome.job_id = id;

    // Wait.
    std::vector<TaskState> tasks(static_cast<size_t>(k), TaskState::unknown);
    int last_done = -1;
    int failures = 0;
    auto failing_since = std::chrono::steady_clock::now();
    bool seen = false;
    bool finished = false;
    auto count_done = [&] {
        return static_cast<int>(std::count(tasks.begin(), tasks.end(), TaskState::finished));
    };
    auto report = [&](int done) {
        if (done != last_done && progress) progress(done, k);
        last_done = done;
    };
    for (int polls = 0; polls < job.max_polls; ++polls) {
        if (polls > 0) std::this_thread::sleep_for(poll_interval);
        Captured q = run_capture(squeue, {"squeue", "-h", "-r", "-t", "all", "-j", id, "-o", "%i %T"},
                                 squeue_timeout_s);
        if (!q.spawned) {
            outcome.error = "squeue failed: " + q.failure;
            return outcome;
        }
        int listed = q.failure.empty() && q.status == 0 ? update_tasks(q.out, id, tasks) : 0;
        if (listed == 0) {
            // Not listed: not visible yet, or purged after it ended (then it has finished).
            if (failures++ == 0) failing_since = std::chrono::steady_clock::now();
            bool gone = q.err.find("Invalid job id") != std::string::npos || (q.failure.empty() && q.status == 0);
            if (gone && (seen || failures > unseen_grace_polls)) {
                finished = true;
                break;
            }
            if (failures >= min_squeue_failures &&
                std::chrono::steady_clock::now() - failing_since > squeue_failure_window) {
                std::string why = !q.failure.empty() ? q.failure : one_line(q.err);
                outcome.error = "squeue failed for job " + id + " " + std::to_string(failures) +
                                " times in a row: " + (why.empty() ? "exit status " + std::to_string(q.status) : why);
                return outcome;
            }
            continue;
        }
        failures = 0;
        seen = true;
        int done = count_done();
        report(done);
        if (done == k) {
            finished = true;
            break;
        }
    }
    if (!finished) {
        outcome.error = "gave up waiting for Slurm job " + id + " after " + std::to_string(job.max_polls) +
                        " polls (" + std::to_string(k - count_done()) + " of " + std::to_string(k) +
                        " tasks still pending or running); it was left queued: scancel " + id + " to stop it";
        return outcome;
    }
    report(k);

    // Verdicts.
    std::vector<int> status(static_cast<size_t>(k), 0);
    std::vector<bool> have(static_cast<size_t>(k), false);
    for (int attempt = 0; attempt <= rc_retries; ++attempt) {
        bool missing = false;
        for (int t = 0; t < k; ++t) {
            if (!have[static_cast<size_t>(t)])
                have[static_cast<size_t>(t)] = read_rc(task_file(job, t, ".rc"), status[static_cast<size_t>(t)]);
            missing = missing || !have[static_cast<size_t>(t)];
        }
        if (!missing || attempt == rc_retries) break;
        std::this_thread::sleep_for(poll_interval);
    }
    std::string first;
    for (int t = 0; t < k; ++t) {
        auto i = static_cast<size_t>(t);
        if (have[i] && status[i] == 0) continue;
        outcome.failed_tasks.push_back(t);
        if (first.empty())
            first = "task " + std::to_string(t) + " failed (" +
                    (have[i] ? "exit " + std::to_string(status[i])
                             : std::string("no exit status: cancelled, killed or out of time")) +
                    "): see " + task_file(job, t, ".log");
    }
    if (!outcome.failed_tasks.empty()) {
        outcome.error = first;
        if (outcome.failed_tasks.size() > 1)
            outcome.error += " (" + std::to_string(outcome.failed_tasks.size()) + " of " + std::to_string(k) +
                             " tasks failed)";
    }
    return outcome;
}

}  // namespace sdv::campaign
