// igi_separate: the out-of-line functions of igi/config.hpp, compiled once for igi's own tests,
// benchmarks and examples.
#include "igi/separate_compilation.hpp"
