#pragma once
// `napkin demo`: builds a catalogue from the padding series (three paddings,
// five oblique head impacts each) and the report's section 4.5 validation
// scenario on its three 3-2-2-2 geometries, processes it in parallel with the
// batch scheduler, and prints what napkin tells about it: the padding
// comparison, the validation table against the known answers, the legacy
// solver's error, the HTML report it wrote, and the commands to try next.
#include <string>
#include <vector>

namespace napkin::cli {

struct DemoRequest {
  std::string dir = "napkin-demo";  // the demo's folder (cli/demo_folder.h)
  int threads = 0;                  // worker threads; 0: all cores
  // The limit sets of the padding verdict (app/limits.h): FMVSS 201U, the
  // free-motion headform's upper-interior limit, the padding case, and Euro
  // NCAP's points for the head (AOP v9.3), to show a sliding scale.
  std::vector<std::string> limits = {"fmvss201u", "euro-ncap-aop-v9.3-frontal-head-hiii50m"};
};

// Runs the demo, printing to standard output. Throws InputError when the
// folder cannot be used (cli/demo_folder.h) or a demo test fails.
void RunDemo(const DemoRequest& request);

}  // namespace napkin::cli
