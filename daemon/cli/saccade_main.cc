// saccade: the user's command line (recognize, bench, demo).
#include "daemon/cli/commands.h"

#include <csignal>
#include <iostream>
#include <string>
#include <vector>

namespace {

constexpr const char* kUsage = R"(usage: saccade <command> [flags]

commands:
  recognize --model M.pcd --scene S.pcd [--fovea x,y,z] [--plain] [--config FILE.yaml] [--json]
            find the model in one scene and print each instance's pose and votes
  bench     --model M.pcd --scene S.pcd --fovea x,y,z [--truth POSE.txt] [--frames N] [--json]
            time plain (gold standard) against foveated recognition on one frame
  bench-track --source SPEC --model M[,M2,...] [--config FILE.yaml] [--name NAME] [--rate HZ]
            [--tolerance-cm C] [--tolerance-deg D] [--wrong-cm W] [--frames-out F.jsonl]
            the tracker on a sequence with truth at the sensor's rate (frames it has no time
            for are dropped): share of visible frames within tolerance, frames to re-acquire,
            frames on a wrong place, costs; the last line is one JSON object
  record    --source SPEC --out DIR [--frames N] [--format pcd|depth|oni|fakenect]
            capture frames (with ground truth when the source has it); SPEC is one of
            openni2://[#N|URI|SERIAL][?registration=auto|device|saccade|none&calibration=F],
            freenect://[N|SERIAL][?calibration=F&raw=1],
            PATH.oni[?mode=realtime|fast|step&loop=1],
            pcd:DIR[?rate=HZ&loop=1], depth:DIR[?intrinsics=FILE&rate=HZ&loop=1],
            synthetic:NAME[?frames=N&seed=S&rate=HZ&loop=1] (NAME: a preset or a YAML file)
  log-fixations --out FILE.csv|FILE.jsonl [--channel SACCADE_FIXATION] [--lcm-url URL]
            [--count N]
            subscribe to saccaded's fixations and log them until SIGINT (or N of them)
  fixations LOG.lcmlog --out FILE.csv|FILE.jsonl [--channel SACCADE_FIXATION]
            convert the fixations in an lcm-logger log to the same format
  segment   --scene S.pcd --out MODEL.pcd [--z-max M] [--plane-fraction F] [--plane-distance D]
            [--cluster-distance D] [--min-points N] [--pick largest|nearest|N] [--seed S] [--json]
            cut an object out of a capture: drop points beyond z_max, remove planes until F of
            the points is gone, cluster the rest; write the picked cluster as a model
  eval      --dataset DIR|SPEC|FILE.pcd --model M --configs FILE.yaml [--out DIR]
            [--model-centre x,y,z] [--truth-pose POSE.txt] [--sphere-radius R]
            [--sweep NAME,...] [--reference NAME] [--frames N] [--repeat N] [--no-plots]
  eval      --cases CASES.yaml [--data DIR] --configs FILE.yaml [--out DIR] [...]
            run recognition configurations over frames with ground truth (or over labelled
            cross-capture cases); write Table 7 style tables (CSV, Markdown), every trial's
            counts and stage times, TP/FP against the distance threshold, the fovea-distance
            sweep (one frame, and frames until the attention loop finds the object), and their
            PNG plots (gnuplot); --repeat N times each trial N times and keeps the median
  demo      [--seed N]
            render a synthetic Kinect scene and find in it a target modelled from another
            capture; exit 1 when the target is not found

exit codes: 0 ok, 1 input could not be processed, 2 bad usage
)";

}  // namespace

int main(int argc, char** argv) {
  std::signal(SIGPIPE, SIG_IGN);  // a closed pipe on stdout fails a write, it does not kill
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "--help" || args[0] == "-h" || args[0] == "help") {
    std::cout << kUsage;
    return args.empty() ? saccade::kExitUsage : saccade::kExitOk;
  }
  const std::string command = args[0];
  args.erase(args.begin());
  if (command == "recognize") return saccade::RunRecognize(args, std::cout, std::cerr);
  if (command == "bench") return saccade::RunBench(args, std::cout, std::cerr);
  if (command == "bench-track") return saccade::RunBenchTrack(args, std::cout, std::cerr);
  if (command == "record") return saccade::RunRecord(args, std::cout, std::cerr);
  if (command == "log-fixations") return saccade::RunLogFixations(args, std::cout, std::cerr);
  if (command == "fixations") return saccade::RunFixations(args, std::cout, std::cerr);
  if (command == "segment") return saccade::RunSegment(args, std::cout, std::cerr);
  if (command == "eval") return saccade::RunEval(args, std::cout, std::cerr);
  if (command == "demo") return saccade::RunDemo(args, std::cout, std::cerr);
  std::cerr << "saccade: unknown command '" << command << "' (see saccade --help)\n";
  return saccade::kExitUsage;
}
