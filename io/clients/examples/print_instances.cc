// Prints where saccaded sees each instance: print_instances [URL] [FRAMES]
#include <lcm/lcm-cpp.hpp>
#include <saccade/detections_t.hpp>

#include <cstdio>
#include <cstdlib>
#include <string>

struct Printer {
  int seen = 0;  // frames with an instance
  void On(const lcm::ReceiveBuffer*, const std::string&, const saccade::detections_t* d) {
    for (const saccade::instance_t& i : d->instances)  // centroid: where the object is
      std::printf("%s at (%.3f, %.3f, %.3f) m in %s, confidence %.2f\n", i.model_name.c_str(),
                  i.centroid[0], i.centroid[1], i.centroid[2], d->frame.c_str(), i.confidence);
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
