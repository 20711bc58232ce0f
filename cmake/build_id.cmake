# build_id.cmake - writes OUT (build_id.h) with BRUME_BUILD_ID: a hash of what makes brume's
# images (every file under src/ and include/, the default scene) and of EXTRA (the compiler,
# its version, the build type and flags). A checkpoint records it (src/job/checkpoint.c), so
# that a render resumes only in the build that wrote it: another build may draw its samples
# differently, and the resumed image would not be the one an uninterrupted render makes.
# Run by CMakeLists.txt at build time; OUT is rewritten only when the hash changes.
file(GLOB_RECURSE files ${ROOT}/src/*.c ${ROOT}/src/*.h ${ROOT}/src/*.cpp ${ROOT}/include/*.h)
list(APPEND files ${ROOT}/scenes/default.json)
list(SORT files)
set(all "${EXTRA}\n")
foreach(f IN LISTS files)
  file(SHA256 ${f} h)
  file(RELATIVE_PATH rel ${ROOT} ${f})
  string(APPEND all "${rel} ${h}\n")
endforeach()
string(SHA256 id "${all}")
string(SUBSTRING "${id}" 0 16 id)
set(text "/* build_id.h - written by cmake/build_id.cmake; do not edit. */\n#define BRUME_BUILD_ID \"${id}\"\n")
set(old "")
if(EXISTS ${OUT})
  file(READ ${OUT} old)
endif()
if(NOT old STREQUAL text)
  file(WRITE ${OUT} "${text}")
endif()
