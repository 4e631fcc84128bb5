# Provenance: the git revision is read at configure time and again at every build, so a binary
# always reports the commit it was built from (with -dirty when the tree had changes).
set(SHAPEPRESS_GENERATED_DIR ${CMAKE_BINARY_DIR}/generated)
file(MAKE_DIRECTORY ${SHAPEPRESS_GENERATED_DIR}/common)
add_custom_target(shapepress_version_header
  COMMAND ${CMAKE_COMMAND} -DSOURCE_DIR=${CMAKE_SOURCE_DIR}
          -DOUTPUT=${SHAPEPRESS_GENERATED_DIR}/common/version_info.hpp
          -DVERSION=${PROJECT_VERSION}
          -P ${CMAKE_SOURCE_DIR}/cmake/WriteVersion.cmake
  BYPRODUCTS ${SHAPEPRESS_GENERATED_DIR}/common/version_info.hpp
  COMMENT "Recording git revision")
