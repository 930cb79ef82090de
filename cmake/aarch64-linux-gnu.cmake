# CMake toolchain for aarch64 with Debian's cross compiler and the arm64
# multiarch packages (scripts/install_deps.sh --aarch64); programs run under
# qemu-user, so ctest and GoogleTest's test discovery work from an x86-64 host.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)
set(CMAKE_LIBRARY_ARCHITECTURE aarch64-linux-gnu)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_CROSSCOMPILING_EMULATOR qemu-aarch64)
set(CMAKE_CXX_FLAGS_INIT "-Wno-psabi")  # GCC notes a C++17 ABI change of std::pair arguments from GCC 10
