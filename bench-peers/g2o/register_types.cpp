// Forces the static registration of g2o's slam3d and slam3d_addons types into
// an executable linked against the g2opy wheel's static libraries: without it
// the linker drops them, and g2o's save() writes an empty graph. This file is
// this project's (bench-peers/g2o/simulate.sh links it into g2o's simulators).
#include "g2o/core/factory.h"

G2O_USE_TYPE_GROUP(slam3d);
G2O_USE_TYPE_GROUP(slam3d_addons);
