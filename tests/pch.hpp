// The precompiled header of the test executables (tests/CMakeLists.txt: compiled once by
// effigi_test_pch, reused by every test_<area>; cmake/EffigiPch.cmake). Parsing Catch2's
// single header and the registry's includes (glm, fmt, <filesystem>, ...) was most of a
// test's compile time. Only headers (nearly) every test includes anyway belong here:
// Catch2, the registry, the standard library.
#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include <fmt/format.h>

#include "effigi/core/registry.hpp"

#include <catch2/catch.hpp>
