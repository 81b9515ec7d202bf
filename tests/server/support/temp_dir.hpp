#pragma once
#include "testing/temp_dir.hpp"

namespace pslam::server::testing {
using pslam::testing::TempDir;
}  // namespace pslam::server::testing
