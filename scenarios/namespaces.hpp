#pragma once
// The scenarios drive the engine and place bodies with the packing library; inside
// shapepress::scenarios both are read unqualified (Engine, SphereState, SphereList).
namespace shapepress::simulate {
class Engine;
}  // namespace shapepress::simulate
namespace shapepress::packing {}

namespace shapepress::scenarios {
using namespace simulate;
using namespace packing;
}  // namespace shapepress::scenarios
