// The libraries' version, from the project's VERSION (CMakeLists.txt passes
// it to the authoring library, which every other library links).
#include <breakables/types.h>

bk_version bk_get_version(void) {
  bk_version version = {BK_VERSION_MAJOR, BK_VERSION_MINOR, BK_VERSION_REVISION};
  return version;
}
