// Prints where saccaded sees each instance, and each track's state changes:
// print_instances [URL] [FRAMES]. Act on TRACKING and RE-ACQUIRED only (docs/LCM.md).
#include <lcm/lcm-cpp.hpp>
#include <saccade/detections_t.hpp>

#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>

// mug for /var/lib/saccade/models/mug.pcd; a spec such as synthetic:target as it is.
std::string ShortName(const std::string& model_name) {
  std::string name = model_name.substr(model_name.find_last_of('/') + 1);
  const std::size_t dot = name.find_last_of('.');
  if (dot != std::string::npos && dot > 0) name.resize(dot);
  return name.empty() ? model_name : name;
}

struct Printer {
  int seen = 0;                       // frames with an instance
  std::map<int, std::string> states;  // track id -> its last state
  void On(const lcm::ReceiveBuffer*, const std::string&, const saccade::detections_t* d) {
    for (const saccade::instance_t& i : d->instances) {
      const std::string name = ShortName(i.model_name);
      const auto last = states.find(i.track_id);
      if (i.track_id >= 0 && (last == states.end() || last->second != i.track_state_name)) {
        std::printf("%s #%d: %s -> %s\n", name.c_str(), i.track_id,
                    last == states.end() ? "NEW" : last->second.c_str(),
                    i.track_state_name.c_str());
        states[i.track_id] = i.track_state_name;
      }
      // centroid: where the object is (trans is the model's origin)
      std::printf("%s #%d %s at (%.3f, %.3f, %.3f) m in %s, confidence %.2f\n", name.c_str(),
                  i.track_id, i.track_state_name.c_str(), i.centroid[0], i.centroid[1],
                  i.centroid[2], d->frame.c_str(), i.confidence);
    }
    std::fflush(stdout);
    seen += d->num_instances > 0;
  }
};

int main(int argc, char** argv) {
  lcm::LCM lcm(argc > 1 ? argv[1] : "udpm://239.255.76.67:7667?ttl=0");
  const int frames = argc > 2 ? std::atoi(argv[2]) : 0;  // 0: until Ctrl-C
  Printer printer;
  lcm.subscribe("SACCADE_DETECTIONS", &Printer::On, &printer);
  while (lcm.good() && (frames == 0 || printer.seen < frames)) lcm.handle();
  return lcm.good() ? 0 : 1;
}
