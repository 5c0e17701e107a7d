/*
 * threads.c - the default thread count: the CPUs this process may run on, not the machine's.
 * A job system hands a job fewer CPUs than the node has (Slurm's cgroup or `taskset -c 0`, seen in
 * the affinity mask; SLURM_CPUS_PER_TASK when the mask is wider than the allocation): starting the
 * machine's count would oversubscribe the job's share.
 */
#define _GNU_SOURCE /* sched_getaffinity, CPU_COUNT */
#include <sched.h>
#include <stdlib.h>
#include <unistd.h>

#include "cli/cli.h"

int qcli_threads_from(long online, long affinity, const char *slurm)
{
    long n = online > 0 ? online : 1;
    if (affinity > 0 && affinity < n)
        n = affinity;
    if (slurm && *slurm) {
        char *end;
        long s = strtol(slurm, &end, 10);
        if (*end == '\0' && s > 0 && s < n) /* a malformed value is ignored, not trusted */
            n = s;
    }
    return n > 256 ? 256 : (int)n;
}

int qcli_default_threads(void)
{
    long affinity = 0;
#ifdef __linux__
    cpu_set_t set;
    if (sched_getaffinity(0, sizeof set, &set) == 0)
        affinity = CPU_COUNT(&set);
#endif
    return qcli_threads_from(sysconf(_SC_NPROCESSORS_ONLN), affinity, getenv("SLURM_CPUS_PER_TASK"));
}
