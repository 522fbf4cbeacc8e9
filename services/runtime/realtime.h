// Real-time scheduling for haptic threads: SCHED_FIFO, locked memory, a
// pinned core, and a mutex that lends its holder the waiter's priority.
// Threads inherit the scheduling of the thread that creates them, Fast
// DDS's own included: a service raises its thread before it creates the
// participant and the endpoints its haptic thread uses, and lowers the
// threads that do other work (docs/haptic.md, "Scheduling").
#pragma once

#include <pthread.h>
#include <string>

namespace hcosim::services::runtime {

struct Scheduling {
  int priority = 0;  // SCHED_FIFO priority 1..99; 0: the normal scheduler
  int cpu = -1;      // core to pin to; -1: any
};

// Gives the calling thread `s` as far as the system allows, and with a
// priority locks the process's memory. A sanitizer build keeps the normal
// scheduler. Never throws for a refusal: returns one line that says what
// the thread got and, for what it did not, why.
std::string apply(const Scheduling& s);

// The calling thread back to the normal scheduler (its affinity kept).
void lower_to_normal();

// The calling thread one SCHED_FIFO priority below `s` (a source's loop,
// after its haptic answers and before everything at normal priority), or
// the normal scheduler when `s` has no priority above 1.
void lower_below(const Scheduling& s);

// A mutex with priority inheritance: a normal-priority holder runs at the
// waiting haptic thread's priority until it unlocks, so that other normal
// work cannot hold the haptic thread off (priority inversion).
class PiMutex {
 public:
  PiMutex();
  ~PiMutex();
  PiMutex(const PiMutex&) = delete;
  PiMutex& operator=(const PiMutex&) = delete;
  void lock();
  void unlock();

 private:
  pthread_mutex_t m_;
};

}  // namespace hcosim::services::runtime
