/* A file that breaks the tool's rule (plugin/cli uses weft.h only): the include check
 * (cmake/check_cli_includes.cmake) must name it. Never compiled. */
#include "model.h"
#include "weft/weft.h"
