# Every dependency comes from Debian's packages (scripts/install-deps.sh installs them).
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(fmt REQUIRED)
find_package(nlohmann_json 3.11 REQUIRED)
find_package(CLI11 REQUIRED)
find_package(NLopt REQUIRED)
find_package(SUNDIALS REQUIRED)
find_package(Ceres REQUIRED)
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
