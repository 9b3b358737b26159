# Version and git revision, written into a generated header at build time (so a new commit
# changes the revision reported by `hertzgear --version` without a re-configure).
set(HERTZGEAR_VERSION_IN ${CMAKE_CURRENT_LIST_DIR}/version.h.in)
set(HERTZGEAR_VERSION_H ${CMAKE_BINARY_DIR}/generated/hertzgear/version.h)
add_custom_target(hertzgear_version_header
  COMMAND ${CMAKE_COMMAND}
          -DSRC=${HERTZGEAR_VERSION_IN} -DDST=${HERTZGEAR_VERSION_H}
          -DVERSION=${PROJECT_VERSION} -DGIT_DIR=${CMAKE_SOURCE_DIR}
          -P ${CMAKE_CURRENT_LIST_DIR}/WriteVersion.cmake
  BYPRODUCTS ${HERTZGEAR_VERSION_H}
  COMMENT "hertzgear version header")
