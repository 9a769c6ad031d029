// SPDX-License-Identifier: Apache-2.0
#include "tests/support/own_memory.h"

#include <fstream>
#include <string>

namespace ispq::testing {

double OwnStatusKib(const char* field) {
  std::ifstream status("/proc/self/status");
  std::string key;
  while (status >> key) {
    if (key == field) {
      double kib = 0;
      status >> kib;
      return kib;
    }
  }
  return 0;
}

}  // namespace ispq::testing
