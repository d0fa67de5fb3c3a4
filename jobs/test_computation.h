#pragma once
// The compute stage of a run (jobs/README.md): the transform core on one
// test read by the reader thread, on a compute thread of the run's arena.
#include "jobs/run_context.h"

namespace napkin::jobs {

// Computes `item`'s result with the context's processing config; an input
// error (bad data) or the failing finding of the verdict (engine/pipeline.h)
// becomes the item's failure sentence, any other exception propagates (and
// stops the run: jobs/README.md "Errors"). Lowers the
// calling thread's priority the first time (jobs/README.md "Priorities").
void ComputeTest(WorkItem& item, RunContext& context);

}  // namespace napkin::jobs
