# The headers kernels of K are compiled against, frozen at build time (run as a build step:
# cmake -DSOURCE_DIR=src -DSNAPSHOT_DIR=dir -DHASH_HEADER=file -P snapshot_headers.cmake).
#
# A kernel is compiled at run time and then called by this very binary, so it must see the
# headers the binary was built from, not the source tree as it is now (edited, pulled, not yet
# rebuilt). The snapshot holds a copy of every header and HEADERS_SHA256, a hash of them all;
# the same hash is compiled into the binary (HASH_HEADER), enters the kernel cache's key, and
# is compared with the snapshot's before any kernel is compiled (kernel_build/kernel_cache.cpp).
file(GLOB_RECURSE headers RELATIVE ${SOURCE_DIR} ${SOURCE_DIR}/*.hpp)
list(SORT headers)
set(listing "")
foreach(header IN LISTS headers)
  file(SHA256 ${SOURCE_DIR}/${header} sum)
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
    configure_file(${SOURCE_DIR}/${header} ${SNAPSHOT_DIR}/${header} COPYONLY)
  endforeach()
  file(WRITE ${SNAPSHOT_DIR}/HEADERS_SHA256 "${hash}\n")
endif()

set(text "// Written at build time by kernel_build/snapshot_headers.cmake.\n#pragma once\n\nnamespace cs {\n// SHA-256 over the headers (path and SHA-256 of each) that kernels of K are compiled against.\ninline constexpr const char* kKernelHeadersHash = \"${hash}\";\n}  // namespace cs\n")
set(current "")
if(EXISTS ${HASH_HEADER})
  file(READ ${HASH_HEADER} current)
endif()
if(NOT current STREQUAL text)
  file(WRITE ${HASH_HEADER} "${text}")
endif()
