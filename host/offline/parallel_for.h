// The host's ParallelFor for the model library (src/ starts no threads): a batch of
// independent tasks on `jobs` threads pulling indices from a shared counter. The first
// exception a task throws stops the batch and is rethrown to the caller.
#pragma once

#include "analysis/steady_state/parallel_for.h"

namespace swum::host {

/// jobs = 0: all cores.
ParallelFor make_parallel_for(unsigned jobs = 0);

/// The number of threads make_parallel_for(jobs) runs.
unsigned parallel_threads(unsigned jobs = 0);

}  // namespace swum::host
