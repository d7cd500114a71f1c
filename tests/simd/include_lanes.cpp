// Preprocessed by the clang AVX-512 guard tests in this folder's CMakeLists.txt.
#include <igi/simd/lanes.hpp>
