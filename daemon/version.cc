// --version: Saccade's own version and commit, and the versions of the libraries it was built
// against (their headers' macros).
#include "daemon/args.h"

#include <OniVersion.h>
#include <lcm/lcm.h>
#include <oneapi/tbb/version.h>
#include <pcl/pcl_config.h>

#include <string>

#include "saccade_git_commit.h"

#define SACCADE_STRINGIFY_(x) #x
#define SACCADE_STRINGIFY(x) SACCADE_STRINGIFY_(x)

namespace saccade {

std::string VersionText(const std::string& program) {
  return program + " " SACCADE_VERSION " (commit " SACCADE_GIT_COMMIT ")\n"
         "built with PCL " PCL_VERSION_PRETTY ", OpenNI2 " SACCADE_STRINGIFY(ONI_VERSION_MAJOR) "."
         SACCADE_STRINGIFY(ONI_VERSION_MINOR) "." SACCADE_STRINGIFY(ONI_VERSION_MAINTENANCE)
         ", LCM " SACCADE_STRINGIFY(LCM_MAJOR_VERSION) "." SACCADE_STRINGIFY(LCM_MINOR_VERSION) "."
         SACCADE_STRINGIFY(LCM_MICRO_VERSION) ", TBB " TBB_VERSION_STRING ", Eigen "
         SACCADE_STRINGIFY(EIGEN_WORLD_VERSION) "." SACCADE_STRINGIFY(EIGEN_MAJOR_VERSION) "."
         SACCADE_STRINGIFY(EIGEN_MINOR_VERSION);
}

}  // namespace saccade
