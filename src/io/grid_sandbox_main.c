/* grid_sandbox_main.c - main() of brume-openvdb-reader, the program libbrume starts to read a
 * .vdb in a process of its own under resource limits (io/grid_sandbox.h); not a command for
 * users. Not part of the library (CMakeLists.txt leaves it out): built and installed beside
 * the OpenVDB module, where the library looks for both. */
#include "io/grid_sandbox.h"

int main(int argc, char **argv)
{
    return grid_sandbox_child_main(argc, argv);
}
