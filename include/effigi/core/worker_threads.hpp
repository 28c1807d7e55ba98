#pragma once
// Joins oneTBB's worker threads when a program's main() returns. Without it the workers
// are still exiting while LeakSanitizer stops the world at exit to look for leaks, and
// its ptrace-based tracer crashes now and then ("Tracer caught signal 11": the asan
// preset's tests failed at random after passing every assertion). Declare one at the top
// of main().
#include <tbb/global_control.h>

#include <new>

namespace effigi {

class WorkerThreadsJoin {
public:
    WorkerThreadsJoin() : m_handle(tbb::attach{}) {}
    ~WorkerThreadsJoin() { tbb::finalize(m_handle, std::nothrow); }
    WorkerThreadsJoin(const WorkerThreadsJoin&) = delete;
    WorkerThreadsJoin& operator=(const WorkerThreadsJoin&) = delete;

private:
    tbb::task_scheduler_handle m_handle;
};

} // namespace effigi
