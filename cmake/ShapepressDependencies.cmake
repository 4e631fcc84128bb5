# Every dependency comes from Debian 12's packages (scripts/install-deps.sh installs them).
find_package(Eigen3 3.3 REQUIRED NO_MODULE)
find_package(OpenMP REQUIRED COMPONENTS CXX)
# hdf5::hdf5: FindHDF5's imported target of the C library (its headers SYSTEM, as imported
# targets' are).
find_package(HDF5 REQUIRED COMPONENTS C)
find_package(tomlplusplus REQUIRED)
find_package(spdlog REQUIRED)
find_package(fmt REQUIRED)
find_package(CLI11 REQUIRED)
find_package(nlohmann_json 3 REQUIRED)
find_package(Threads REQUIRED)
find_package(OpenSSL 3 REQUIRED COMPONENTS Crypto)
find_package(OpenCV REQUIRED COMPONENTS core imgproc imgcodecs)
find_package(CGAL REQUIRED)
find_package(NLopt 2.7 REQUIRED)
# OpenVDB installs a find module (FindOpenVDB.cmake), not a package config, in its own folder
# beside the libraries: look for it under the install prefixes, in this compiler's multiarch
# folder (Debian's lib/x86_64-linux-gnu, lib/aarch64-linux-gnu, …) or a plain lib/. A user's
# -DSHAPEPRESS_OPENVDB_MODULE_DIR=… or CMAKE_MODULE_PATH wins.
find_path(SHAPEPRESS_OPENVDB_MODULE_DIR FindOpenVDB.cmake
  PATHS ${CMAKE_PREFIX_PATH} ${CMAKE_SYSTEM_PREFIX_PATH}
  PATH_SUFFIXES lib/${CMAKE_LIBRARY_ARCHITECTURE}/cmake/OpenVDB lib/cmake/OpenVDB
                lib64/cmake/OpenVDB
  NO_DEFAULT_PATH
  DOC "folder of OpenVDB's FindOpenVDB.cmake")
if(SHAPEPRESS_OPENVDB_MODULE_DIR)
  list(APPEND CMAKE_MODULE_PATH ${SHAPEPRESS_OPENVDB_MODULE_DIR})
endif()
find_package(OpenVDB REQUIRED)

if(SHAPEPRESS_TESTS)
  find_package(GTest REQUIRED)
  include(GoogleTest)
endif()
if(SHAPEPRESS_BENCHMARKS)
  find_package(benchmark REQUIRED)
endif()
