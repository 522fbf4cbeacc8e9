// hcosim: one entry point for running, inspecting and measuring deployments.
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "services/bench/bench.h"
#include "services/cli/cli.h"
#include "services/runtime/service.h"

namespace {

const char* kUsage = R"(usage: hcosim COMMAND [ARGS]

Commands:
  up FILE [--duration S] [--mode realtime|lockstep] [--out DIR] [--record REC]
        start the services of a deployment file, each in its own process,
        and stop them all at the end, on Ctrl-C, or when one fails; with
        --record, record every topic of the run
  topics [--domain D] [--wait S]
        list the topics and types seen on a domain
  echo TOPIC [--count N] [--timeout S] [--domain D]
        print samples of one of hcosim's topics as JSON lines
  hz TOPIC [--duration S] [--domain D]
        measure the rate at which a topic's samples arrive
  record REC [--topics T1,T2] [--duration S] [--domain D]
        record topics (all by default) into a recording (docs/recording.md)
  record --out FILE.csv [--device NAME] [--duration S] [--domain D]
        write a haptic device's HapticState as a trajectory the replay device plays
  export REC --topic TOPIC [--format jsonl|csv] [--wall]
        print one topic of a recording, one sample a line, in step order
  replay REC [--topics T1,T2] [--speed X] [--clock sim|receive] [--wait S] [--domain D]
        publish a recording's samples again on their simulated-time schedule
        (or the one they were received on)
  bench SUITE|all|list [--quick] --out DIR
        run one benchmark suite or all of them (soak, half an hour, only when
        named); write DIR/SUITE.json per suite, its plots, and DIR/index.md,
        the report (docs/PERFORMANCE.md)
  track --source VIDEO_OR_FOLDER --camera INTRINSICS.yaml --tag-size M --out POSES.jsonl
        [--truth TRUTH.jsonl] [--family F] [--decimate D] [--sigma S] [--threads N]
        detect AprilTags in a video or an image folder, one JSON line per
        detection; with --truth, the errors against known poses
  synth --out DIR [--frames N] [--rate HZ] [--resolution WxH] [--condition C] [--video]
        write a synthetic marker sequence (PNG frames, camera.yaml, truth.jsonl)
  video FILE
        count a video's frames, and those that are blank (one flat colour)
  security init [DIR] [--deployment FILE] [--identities A,B] [--readers R] [--protection data|all]
        [--days N] [--force|--keep]
        make a test CA, a certificate per service of FILE (and for the tools,
        the clock and A, B; R may only subscribe) and signed governance and
        permissions documents in DIR, else FILE's security dir (docs/security.md);
        a DIR that holds a CA is replaced with --force, kept with --keep;
        --protection all also encrypts every RTPS message, not only payloads
        and discovery

The domain defaults to $HCOSIM_DOMAIN, else 0. Topics: docs/topics.md.
topics, echo, hz, record and replay join a secure domain with --security DIR
(else $HCOSIM_SECURITY) as --identity NAME (default hcosim).
)";

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h") || !std::strcmp(argv[1], "help")) {
    std::cout << kUsage;
    return argc < 2 ? 2 : 0;
  }
  const std::string cmd = argv[1];
  const std::vector<std::string> rest(argv + 2, argv + argc);
  return hcosim::services::runtime::guarded_main("hcosim", [&]() -> int {
    using namespace hcosim::services::cli;
    if (cmd == "up") return up(rest);
    if (cmd == "topics") return topics(rest);
    if (cmd == "echo") return echo(rest);
    if (cmd == "hz") return hz(rest);
    if (cmd == "bench") return hcosim::services::bench::command(rest);
    if (cmd == "record") return record(rest);
    if (cmd == "track") return track(rest);
    if (cmd == "synth") return synth(rest);
    if (cmd == "video") return video(rest);
    if (cmd == "export") return export_recording(rest);
    if (cmd == "replay") return replay(rest);
    if (cmd == "security") return security(rest);
    if (cmd == "bench-peer") return hcosim::services::bench::peer_command(rest);
    std::cerr << "hcosim: unknown command '" << cmd << "'\n\n" << kUsage;
    return 2;
  });
}
