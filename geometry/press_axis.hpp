#pragma once
// The axis the plate tests press a particle along (geometry/press_frame.hpp): a principal axis of
// its inertia (short: the largest moment, long: the smallest) or a given direction. Free of
// Eigen, so configs can name it.

namespace shapepress::geometry {

enum class PressAxis { short_axis, middle_axis, long_axis, direction };
const char* press_axis_name(PressAxis axis);  // "short", "middle", "long", "direction"

}  // namespace shapepress::geometry
