// The loaded library's version (include/rtd/version.h).
#include "rtd/version.h"

namespace rtd {

const char* versionString() { return RTD_VERSION_STRING; }
int version() { return RTD_VERSION; }

}  // namespace rtd
