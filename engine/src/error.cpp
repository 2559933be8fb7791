#include "gimg/engine/error.h"
