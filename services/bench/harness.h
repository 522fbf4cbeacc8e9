// What the suites share to run hcosim itself: this executable again in a
// child (a peer, a reader, `hcosim up`), a deployment of the default scene
// for real-time runs, and waiting on and stopping those children.
#pragma once

#include <sys/types.h>

#include <filesystem>
#include <string>
#include <vector>

namespace hcosim::services::bench {

// Runs this executable with `args` in a child, behind the command `on`
// (a host's, Hosts::exec) if any.
pid_t start_self(const std::vector<std::string>& on, const std::vector<std::string>& args);

// deploy/default.yaml's scene and services in real time on `domain`, its
// tour repeated to last `seconds`, for `duration` s (0: until stopped), the
// device's closing report written to `device_report` when one is named;
// written into `dir` (its deploy.yaml, returned).
std::filesystem::path default_deployment(const std::filesystem::path& dir, int domain, double seconds, double duration,
                                         const std::filesystem::path& device_report = {});

// `hcosim up DEPLOYMENT --out OUT` in a child process, its output to `log`;
// with `--record RECORD` when one is named.
pid_t start_up(const std::filesystem::path& deployment, const std::filesystem::path& out,
               const std::filesystem::path& log, const std::filesystem::path& record = {});

// Waits until `up` (from start_up, its output in `log`) says every service
// runs; if it exits first or has not within 120 s, stops it and throws
// naming `what` and the log.
void wait_running(pid_t up, const std::filesystem::path& log, const std::string& what);

// A file's whole text ("" when it cannot be read).
std::string read_all(const std::filesystem::path& file);

// Waits up to `seconds` for `pid`, then stops it (SIGTERM); true if it exited 0.
bool reap(pid_t pid, double seconds);

// Stops a child at once (SIGTERM) and waits for it.
void stop(pid_t pid);

}  // namespace hcosim::services::bench
