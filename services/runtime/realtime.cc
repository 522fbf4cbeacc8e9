#include "services/runtime/realtime.h"

#include <sched.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <unistd.h>
#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace hcosim::services::runtime {
namespace {

#if defined(__SANITIZE_ADDRESS__)
constexpr bool kSanitized = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kSanitized = true;
#else
constexpr bool kSanitized = false;
#endif
#else
constexpr bool kSanitized = false;
#endif

std::string rtprio_limit() {
  rlimit r{};
  if (getrlimit(RLIMIT_RTPRIO, &r) != 0) return "unknown";
  return r.rlim_cur == RLIM_INFINITY ? "unlimited" : std::to_string(r.rlim_cur);
}

// Locking memory with a finite limit would make later allocations fail
// once past it; only an unlimited (or root's) limit locks future pages.
std::string lock_memory() {
  rlimit r{};
  getrlimit(RLIMIT_MEMLOCK, &r);
  if (r.rlim_cur != RLIM_INFINITY && geteuid() != 0) return "memory not locked (RLIMIT_MEMLOCK is finite)";
  if (mlockall(MCL_CURRENT | MCL_FUTURE) != 0) return std::string("memory not locked (") + std::strerror(errno) + ")";
  return "memory locked";
}

}  // namespace

std::string apply(const Scheduling& s) {
  std::string out;
  if (s.priority > 0 && kSanitized) {
    // A sanitizer slows every thread several times: a FIFO thread doing a
    // 1 kHz loop's work would then take a core from everything else.
    out = "normal scheduler (SCHED_FIFO " + std::to_string(s.priority) + " not taken in a sanitizer build)";
  } else if (s.priority > 0) {
    sched_param p{};
    p.sched_priority = s.priority;
    const int e = pthread_setschedparam(pthread_self(), SCHED_FIFO, &p);
    if (e == 0)
      out = "SCHED_FIFO " + std::to_string(s.priority) + ", " + lock_memory();
    else
      out = "normal scheduler (SCHED_FIFO " + std::to_string(s.priority) + " refused: " + std::strerror(e) +
            "; RLIMIT_RTPRIO " + rtprio_limit() + ")";
  } else {
    out = "normal scheduler";
  }
  if (s.cpu >= 0) {
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET(s.cpu, &set);
    const int e = pthread_setaffinity_np(pthread_self(), sizeof set, &set);
    out += e == 0 ? ", cpu " + std::to_string(s.cpu)
                  : ", not pinned to cpu " + std::to_string(s.cpu) + " (" + std::strerror(e) + ")";
  }
  return out;
}

void lower_to_normal() {
  sched_param p{};
  pthread_setschedparam(pthread_self(), SCHED_OTHER, &p);
}

void lower_below(const Scheduling& s) {
  // Never raises: a thread the system (or a sanitizer build) left at the
  // normal scheduler stays there.
  int policy = SCHED_OTHER;
  sched_param now{};
  pthread_getschedparam(pthread_self(), &policy, &now);
  if (policy != SCHED_FIFO || s.priority <= 1 || now.sched_priority < s.priority) return lower_to_normal();
  sched_param p{};
  p.sched_priority = s.priority - 1;
  if (pthread_setschedparam(pthread_self(), SCHED_FIFO, &p) != 0) lower_to_normal();
}

PiMutex::PiMutex() {
  pthread_mutexattr_t a;
  pthread_mutexattr_init(&a);
  pthread_mutexattr_setprotocol(&a, PTHREAD_PRIO_INHERIT);
  const int e = pthread_mutex_init(&m_, &a);
  pthread_mutexattr_destroy(&a);
  if (e != 0) throw std::runtime_error(std::string("cannot make a priority-inheriting mutex: ") + std::strerror(e));
}

PiMutex::~PiMutex() { pthread_mutex_destroy(&m_); }
void PiMutex::lock() { pthread_mutex_lock(&m_); }
void PiMutex::unlock() { pthread_mutex_unlock(&m_); }

}  // namespace hcosim::services::runtime
