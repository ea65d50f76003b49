// The precompiled header of most test programs (tests/CMakeLists.txt): GoogleTest, the standard
// headers and hedra's core headers, parsed once per build instead of once per program (about
// 2 s of each test's compilation with GCC -O3). Each test still includes what it uses.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "hedra/core/body.h"
#include "hedra/core/error.h"
#include "hedra/core/primitives.h"
