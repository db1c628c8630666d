# Every dependency, from Debian 12's packages (scripts/setup installs them).
# CGAL is header-only; the dD kernel (Epick_d) needs Eigen through CGAL's support module.
find_package(CGAL 5.5 REQUIRED)
find_package(Eigen3 3.3 REQUIRED NO_MODULE)
include(CGAL_Eigen3_support)

# ITK 5.2: only the modules mesh4d reads images and computes distance maps with.
find_package(ITK 5.2 REQUIRED COMPONENTS ITKCommon ITKDistanceMap ITKImageIntensity
                                         ITKIOImageBase ITKIOMeta ITKIONIFTI ITKIONRRD)

# Protobuf through CMake's FindProtobuf module (Debian ships no protobuf CMake config);
# gRPC through its own config, which brings the C++ code generator plugin.
find_package(Protobuf REQUIRED)
find_package(gRPC CONFIG REQUIRED)

find_package(nlohmann_json 3.11 REQUIRED)
# Debian's prometheus-cpp config has no version file, so no version is requested.
find_package(prometheus-cpp CONFIG REQUIRED)
# civetweb (brought by prometheus-cpp) also serves the REST face.
find_package(civetweb CONFIG REQUIRED)
find_package(CLI11 CONFIG REQUIRED)
find_package(spdlog CONFIG REQUIRED)
find_package(OpenSSL REQUIRED)
find_package(ZLIB REQUIRED)
find_package(Threads REQUIRED)

if(MESH4D_BUILD_TESTS)
  find_package(GTest REQUIRED)
  include(GoogleTest)
endif()
