# Third-party libraries, all from Debian 12 packages (scripts/install-deps.sh).
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(CLI11 REQUIRED)
find_package(tomlplusplus REQUIRED)
find_package(nlohmann_json 3.10 REQUIRED)
# tinygltf (drape.glb): Debian builds the header-only library as libtinygltf (on nlohmann-json and stb).
find_package(TinyGLTF REQUIRED)
find_package(embree 3 REQUIRED)
find_package(OpenMP REQUIRED)
find_package(Threads REQUIRED)
# oneTBB: the solver's threads (the model's local terms, the two sides of the factorisation);
# its idle workers sleep soon, so a busy machine is not slowed by threads spinning.
find_package(TBB REQUIRED)

# stb (stb_image_write, and stb_easy_font for shadow.png's labels): Debian ships the implementations as libstb.
find_path(STB_INCLUDE_DIR stb/stb_image_write.h REQUIRED)
find_library(STB_LIBRARY stb REQUIRED)
add_library(woven_stb INTERFACE)
target_include_directories(woven_stb INTERFACE ${STB_INCLUDE_DIR})
target_link_libraries(woven_stb INTERFACE ${STB_LIBRARY})

# cairo (the plots, render/plot.cpp): one drawing API for the PNG files and the report's inline
# SVG, with real font rendering (DejaVu Sans through fontconfig). pkg-config's absolute paths, so
# that the exported static libraries carry it as they carry stb.
find_package(PkgConfig REQUIRED)
pkg_check_modules(CAIRO REQUIRED cairo)
add_library(woven_cairo INTERFACE)
target_include_directories(woven_cairo SYSTEM INTERFACE ${CAIRO_INCLUDE_DIRS})
target_link_libraries(woven_cairo INTERFACE ${CAIRO_LINK_LIBRARIES})

# CHOLMOD (SuiteSparse) through Eigen's CholmodSupport: supernodal sparse Cholesky for the fast
# solver's Newton systems. Debian 12's SuiteSparse 5 ships no CMake or pkg-config files.
find_path(CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse REQUIRED)
find_library(CHOLMOD_LIBRARY cholmod REQUIRED)
add_library(woven_cholmod INTERFACE)
target_include_directories(woven_cholmod SYSTEM INTERFACE ${CHOLMOD_INCLUDE_DIR})
target_link_libraries(woven_cholmod INTERFACE ${CHOLMOD_LIBRARY} ${CMAKE_DL_LIBS})
# LAPACK (OpenBLAS's, under CHOLMOD too): the dense separator of the two-thread factorisation.
find_package(LAPACK REQUIRED)
