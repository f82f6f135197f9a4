# CMake toolchain file: cross-compile for 64-bit ARM Linux with Debian's cross compiler
# (package g++-aarch64-linux-gnu) against Debian multiarch libraries (packages :arm64,
# installed under /usr/lib/aarch64-linux-gnu; headers shared in /usr/include).
# Test executables run under qemu-user (CMAKE_CROSSCOMPILING_EMULATOR is honoured by
# add_test and gtest_discover_tests). Used by tools/cross_aarch64.sh.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)
set(CMAKE_LIBRARY_ARCHITECTURE aarch64-linux-gnu)
# GCC notes (not warnings) that std::pair<double, double> is passed as in C++14 since
# GCC 10.1 on this ABI: informational, and deploysim passes no such type across libraries
# built by different compilers.
set(CMAKE_CXX_FLAGS_INIT "-Wno-psabi")
# Executables are linked statically: under Debian 12's qemu-user 7.2 a dynamically linked
# aarch64 program (run with -L /usr/aarch64-linux-gnu) hangs at its first pthread_create
# (seen with a five-line C program), while the same program linked statically runs its
# threads. The thread-safety tests need threads.
set(CMAKE_EXE_LINKER_FLAGS_INIT "-static")

# Target libraries come from the multiarch directories of the host root (not a separate
# sysroot), so the package search is not confined to a root path; programs are the host's.
set(CMAKE_FIND_ROOT_PATH /usr/aarch64-linux-gnu)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY BOTH)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE BOTH)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE BOTH)

set(CMAKE_CROSSCOMPILING_EMULATOR qemu-aarch64 -L /usr/aarch64-linux-gnu
    CACHE STRING "Runs target executables on the build machine")
