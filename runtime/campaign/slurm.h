// `sdv sweep --slurm`: the sweep's slices as ONE Slurm job array. Owns the batch script (one
// slice per array task), its submission with `sbatch --parsable`, the wait (polling `squeue`,
// never `sbatch --wait`) and each task's verdict, read from the exit-status file the script
// writes (so success does not depend on Slurm accounting). Merging the slices' rows is the
// sweep's job (sweep.h), not this file's.
//
// work_dir/slurm/sweep.sbatch      the script submitted
// work_dir/slurm/task-<id>.log     stdout and stderr of array task <id>
// work_dir/slurm/task-<id>.rc      its exit status, one line (written .part, then renamed)
//
// Slurm's commands are found on PATH and run with this process's environment (SLURM_CONF
// included). Nothing here throws; every failure is a one-line `error`.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace sdv::campaign {

struct SlurmJob {
    std::string work_dir;              // absolute; the sweep's output directory; the script, logs and
                                       // per-task exit files go to work_dir/slurm/
    std::vector<std::string> command;  // absolute argv of one task, e.g. {"/abs/sdv","sweep",
                                       // "/abs/f.sdv","-o","/abs/dir","--jobs","1"}; the script
                                       // appends "--slice" "$SLURM_ARRAY_TASK_ID/K"
    int array_tasks = 4;               // K: tasks 0..K-1
    std::string partition;             // empty: the cluster's default
    int cpus_per_task = 1;
    std::string job_name = "sdv-sweep";
    // The wait gives up (with an error naming the job, which is left to run) after this many
    // squeue polls, 0.5 s apart: 172800 is a day.
    int max_polls = 172800;
};

// The batch script (bash) that runs one slice per array task; every argument shell-quoted;
// writes the task's exit status to work_dir/slurm/task-<id>.rc (written atomically: .part then
// rename) so that success does not depend on accounting.
std::string slurm_script(const SlurmJob& job);

struct SlurmOutcome {
    std::string error;              // "" on success, else one line
    std::string job_id;             // once submitted
    std::vector<int> failed_tasks;  // ascending
};

// Writes work_dir/slurm/sweep.sbatch, submits it with `sbatch --parsable`, polls
// `squeue -h -r -t all -j JOBID -o "%i %T"` every 0.5 s until no task is pending or running (calling
// progress(done, total) whenever the count of finished tasks changes; it may be empty), then
// reads every task's .rc file: a missing file or a non-zero status marks the task failed.
// squeue failing right after the submission (job not yet visible) is tolerated for a few polls,
// and a failing squeue (controller restarting) for two minutes; a job that has left squeue
// counts as finished. A task found failed does not stop the others: all of them are waited for.
SlurmOutcome slurm_run(const SlurmJob& job, const std::function<void(int done, int total)>& progress);

}  // namespace sdv::campaign
