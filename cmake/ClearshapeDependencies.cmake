# Every dependency comes from Debian's packages (scripts/install-deps.sh installs them).
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(fmt REQUIRED)
find_package(nlohmann_json 3.11 REQUIRED)
find_package(CLI11 REQUIRED)
find_package(NLopt REQUIRED)
find_package(SUNDIALS REQUIRED)
# BLAS is linked as the generic libblas.so.3/liblapack.so.3 (Debian's alternatives pick ATLAS,
# OpenBLAS or the reference implementation on the user's machine), never ATLAS's own
# libf77blas/libatlas, which would make the .deb need libatlas3-base (docs/package.md): FindBLAS
# (run for SuiteSparse) would try ATLAS first, and Debian 12's static Ceres target lists the
# ATLAS libraries of Debian's build host after the generic libblas.so, which exports every
# BLAS symbol they do.
if(NOT DEFINED BLA_VENDOR)
  set(BLA_VENDOR Generic)
endif()
find_package(Ceres REQUIRED)
get_target_property(_ceres_link Ceres::ceres INTERFACE_LINK_LIBRARIES)
list(FILTER _ceres_link EXCLUDE REGEX "/lib(f77blas|atlas)\\.so$")
set_target_properties(Ceres::ceres PROPERTIES INTERFACE_LINK_LIBRARIES "${_ceres_link}")
# Boost.Odeint (plant/fixed_step.cpp) and Boost.Math (ident/residuals.cpp, χ² and normal): header-only, in the system include path; checked here, not
# linked, so the exported static libraries carry no Boost target for a consumer to find.
find_package(Boost 1.74 REQUIRED)
find_package(PkgConfig REQUIRED)
pkg_check_modules(tomlplusplus REQUIRED IMPORTED_TARGET tomlplusplus)
pkg_check_modules(libserialport REQUIRED IMPORTED_TARGET libserialport)  # rig::SerialRig
find_package(Threads REQUIRED)
# The arm (docs/arm.md): URDF through urdfdom, rigid-body dynamics from Orocos KDL. urdfdom's
# pkg-config entry is read for its libraries only (its include directory is /usr/include).
find_package(orocos_kdl 1.4 REQUIRED)
pkg_check_modules(urdfdom REQUIRED urdfdom)
if(CLEARSHAPE_BUILD_TESTS OR CLEARSHAPE_BUILD_EXAMPLES)
  find_package(GTest REQUIRED)
endif()
if(CLEARSHAPE_BUILD_BENCHMARKS)
  find_package(benchmark REQUIRED)
endif()
