# Requirement: dynamics/ shall not mention deal.II (it builds with Eigen and SUNDIALS only).
file(GLOB_RECURSE files ${DIR}/*)
foreach(f ${files})
  file(STRINGS ${f} hits REGEX "deal[.]II|dealii")
  if(hits)
    message(FATAL_ERROR "${f} mentions deal.II: ${hits}")
  endif()
endforeach()
message(STATUS "dynamics/: no deal.II in ${CMAKE_ARGC} files checked")
