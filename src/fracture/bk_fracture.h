// fracture (private): the authoring API plus geom's shared utilities, for
// the fracture files. Not installed: the public API is <breakables/authoring.h>.
#pragma once

#include <breakables/authoring.h>

#include "bk_geom.h"
