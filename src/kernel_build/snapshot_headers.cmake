# The headers kernels of K are compiled against, frozen at build time (run as a build step:
# cmake -DSOURCE_DIR=src -DGENERATED_DIR=dir -DSNAPSHOT_DIR=dir -DHASH_HEADER=file
# -P snapshot_headers.cmake). GENERATED_DIR holds headers generated in src/'s layout
# (numerics/method_list.hpp): they join the snapshot as if they were in src/.
#
# A kernel is compiled at run time and then called by this very binary, so it must see the
# headers the binary was built from, not the source tree as it is now (edited, pulled, not yet
# rebuilt). The snapshot holds a copy of every header and HEADERS_SHA256, a hash of them all;
# the same hash is compiled into the binary (HASH_HEADER), enters the kernel cache's key, and
# is compared with the snapshot's before any kernel is compiled (kernel_build/kernel_cache.cpp).
include(${CMAKE_CURRENT_LIST_DIR}/../../cmake/write_if_changed.cmake)

file(GLOB_RECURSE source_headers RELATIVE ${SOURCE_DIR} ${SOURCE_DIR}/*.hpp)
file(GLOB_RECURSE generated_headers RELATIVE ${GENERATED_DIR} ${GENERATED_DIR}/*.hpp)
set(headers ${source_headers} ${generated_headers})
list(SORT headers)
foreach(header IN LISTS source_headers)
  set(origin_${header} ${SOURCE_DIR})
endforeach()
foreach(header IN LISTS generated_headers)
  if(DEFINED origin_${header})
    message(FATAL_ERROR "${header} is both in ${SOURCE_DIR} and generated in ${GENERATED_DIR}")
  endif()
  set(origin_${header} ${GENERATED_DIR})
endforeach()
set(listing "")
foreach(header IN LISTS headers)
  file(SHA256 ${origin_${header}}/${header} sum)
  string(APPEND listing "${header} ${sum}\n")
endforeach()
string(SHA256 hash "${listing}")

set(old_hash "")
if(EXISTS ${SNAPSHOT_DIR}/HEADERS_SHA256)
  file(READ ${SNAPSHOT_DIR}/HEADERS_SHA256 old_hash)
  string(STRIP "${old_hash}" old_hash)
endif()
if(NOT old_hash STREQUAL hash)
  file(REMOVE_RECURSE ${SNAPSHOT_DIR})
  foreach(header IN LISTS headers)
    configure_file(${origin_${header}}/${header} ${SNAPSHOT_DIR}/${header} COPYONLY)
  endforeach()
  file(WRITE ${SNAPSHOT_DIR}/HEADERS_SHA256 "${hash}\n")
endif()

set(text "// Written at build time by kernel_build/snapshot_headers.cmake.\n#pragma once\n\nnamespace cs {\n// SHA-256 over the headers (path and SHA-256 of each) that kernels of K are compiled against.\ninline constexpr const char* kKernelHeadersHash = \"${hash}\";\n}  // namespace cs\n")
write_if_changed(${HASH_HEADER} "${text}")
