#include "gmwm/version.h"

namespace gmwm {

const char* library_version() { return GMWM_VERSION_STRING; }

}  // namespace gmwm
