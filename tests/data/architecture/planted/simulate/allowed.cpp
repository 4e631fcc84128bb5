// An include the links allow (simulate/ links common/): the check must not name this file.
#include "common/error.hpp"
#include "simulate/engine.hpp"
