# The Debian packages igi's headers build against; shared by the build and the installed config.
find_package(glm CONFIG REQUIRED)
find_package(TinyGLTF CONFIG REQUIRED)
find_package(tinyexr CONFIG REQUIRED)
find_package(TBB CONFIG REQUIRED)
find_package(embree 3 CONFIG REQUIRED)
find_package(PkgConfig REQUIRED)
if(NOT TARGET PkgConfig::STB)
  pkg_check_modules(STB REQUIRED IMPORTED_TARGET GLOBAL stb)
endif()
# MPI is optional (igi::distributed only): QUIET so find_package(igi) works without it.
find_package(MPI QUIET COMPONENTS CXX)
