// GoogleTest prints an SdoAbort as its code and CiA 301's text ("0x06090030 invalid value for
// parameter (download only)") instead of its bytes.
#pragma once

#include <cstdio>
#include <ostream>

#include "object_dictionary.h"

namespace swum::canopen {

inline void PrintTo(SdoAbort code, std::ostream* out) {
  char hex[16];
  std::snprintf(hex, sizeof hex, "0x%08X", static_cast<unsigned>(code));
  *out << hex << " " << describe(code);
}

}  // namespace swum::canopen
