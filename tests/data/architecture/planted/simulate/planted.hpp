#pragma once
// A planted include against the links, for tests/architecture: simulate/ does not link
// scenarios/, so the include-direction check must name this file.
#include "common/error.hpp"
#include "scenarios/compact.hpp"
