# Requirement: the layering rules of docs/architecture.md hold in the sources, not only in the
# links:
#   FORBIDDEN (a ;-list of folders): no file under DIR includes a header of those folders;
#   NO_DEALII: no file under DIR mentions deal.II (dynamics/ builds with Eigen and SUNDIALS only).
#   cmake -DDIR=<folder> [-DFORBIDDEN="dynamics;stiffness"] [-DNO_DEALII=ON] -P check_layering.cmake
set(patterns)
foreach(folder ${FORBIDDEN})
  list(APPEND patterns "#[ \t]*include[ \t]*[\"<]${folder}/")
endforeach()
if(NO_DEALII)
  list(APPEND patterns "deal[.]II|dealii")
endif()
file(GLOB_RECURSE files ${DIR}/*)
list(LENGTH files n_files)
foreach(f ${files})
  foreach(pattern ${patterns})
    file(STRINGS ${f} hits REGEX "${pattern}")
    if(hits)
      message(FATAL_ERROR "${f} breaks the layering rule '${pattern}': ${hits}")
    endif()
  endforeach()
endforeach()
message(STATUS "${DIR}: ${n_files} files keep the layering rules")
