# embed_ptx.cmake - writes the PTX that clang made from src/gpu/kernel.cu as a C string
# (gpu_ptx, gpu/cuda.h). Fails the build when the PTX calls a function it does not define
# (an `.extern .func`: something of the host's that the estimator reached, which the driver
# could not resolve at load time).
#   cmake -DPTX=kernel.ptx -DOUT=gpu_ptx.c -P embed_ptx.cmake
file(READ ${PTX} text)
string(REGEX MATCH "\\.extern \\.func[^\n]*" ext "${text}")
if(ext)
  message(FATAL_ERROR "src/gpu/kernel.cu: the GPU kernels call a function the device does not have: ${ext}")
endif()
file(READ ${PTX} hex HEX)
string(REGEX REPLACE "([0-9a-f][0-9a-f])" "0x\\1," hex "${hex}")
file(WRITE ${OUT}.new "/* gpu_ptx.c - generated from src/gpu/kernel.cu by clang and cmake/embed_ptx.cmake. */\n"
                      "const char gpu_ptx[] = {${hex} 0x00};\n")
file(RENAME ${OUT}.new ${OUT})
