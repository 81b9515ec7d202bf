#pragma once
#include "testing/temp_dir.hpp"

namespace pslam::agent::testing {
using pslam::testing::TempDir;
}  // namespace pslam::agent::testing
