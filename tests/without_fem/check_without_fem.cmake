# Requirement: `cmake -DHERTZGEAR_WITH_FEM=OFF` builds the whole command line without deal.II,
# PETSc or gmsh; its `hertzgear run` (the README's main job: both paper pairs on the shipped
# tables) works; and a scene or command that needs the FE stage is refused with exit 2 and a
# message naming the build option.
#   cmake -DSRC=<source dir> -DWORK=<scratch dir> -P check_without_fem.cmake
file(REMOVE_RECURSE ${WORK})
execute_process(COMMAND ${CMAKE_COMMAND} -S ${SRC} -B ${WORK}/build -DCMAKE_BUILD_TYPE=Release
                        -DHERTZGEAR_WITH_FEM=OFF -DHERTZGEAR_BUILD_TESTS=OFF
                        -DHERTZGEAR_BUILD_BENCH=OFF
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "configuring without the FE stage failed:\n${out}\n${err}")
endif()
# No FE library may be found or linked.
file(READ ${WORK}/build/CMakeCache.txt cache)
if(cache MATCHES "deal.II_DIR:PATH=/" OR cache MATCHES "GMSH_LIBRARY:FILEPATH=/")
  message(FATAL_ERROR "the build without the FE stage looked up deal.II or gmsh")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} --build ${WORK}/build -j 2 --target hertzgear
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "building without the FE stage failed:\n${out}\n${err}")
endif()
set(exe ${WORK}/build/app/hertzgear)
execute_process(COMMAND ldd ${exe} OUTPUT_VARIABLE libs)
if(libs MATCHES "deal|petsc|gmsh|mpi")
  message(FATAL_ERROR "hertzgear without the FE stage links an FE library:\n${libs}")
endif()

# The main job on the shipped tables (a shorter integration; the report is tested elsewhere).
execute_process(COMMAND ${exe} run --out ${WORK}/paper
                WORKING_DIRECTORY ${SRC} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "hertzgear run without the FE stage failed (${rc}):\n${out}\n${err}")
endif()
foreach(pair paper_crowned paper_uncrowned)
  if(NOT EXISTS ${WORK}/paper/${pair}/summary.json)
    message(FATAL_ERROR "hertzgear run wrote no ${pair}/summary.json")
  endif()
endforeach()

# A closed-form source works; the FE source and an FE command are refused with exit 2.
execute_process(COMMAND ${exe} stiffness ${SRC}/data/scenes/paper_crowned.prm --out ${WORK}/iso
                        --set Stiffness/source=iso6336
                RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT EXISTS ${WORK}/iso/stiffness.json)
  message(FATAL_ERROR "the iso6336 source without the FE stage failed (${rc}): ${err}")
endif()
foreach(args "stiffness;${SRC}/data/scenes/paper_crowned.prm;--out;${WORK}/fem"
             "mesh;${SRC}/data/scenes/paper_crowned.prm;--out;${WORK}/mesh"
             "validate;hertz;--coarse")
  execute_process(COMMAND ${exe} ${args} RESULT_VARIABLE rc ERROR_VARIABLE err)
  if(NOT rc EQUAL 2 OR NOT err MATCHES "HERTZGEAR_WITH_FEM")
    message(FATAL_ERROR "`hertzgear ${args}` without the FE stage: exit ${rc}, expected 2 with a "
                        "message naming HERTZGEAR_WITH_FEM: ${err}")
  endif()
endforeach()
if(EXISTS ${WORK}/fem OR EXISTS ${WORK}/mesh)
  message(FATAL_ERROR "a refused FE command left a folder behind")
endif()
message(STATUS "hertzgear without the FE stage: built, ran the paper pairs, refused the FE stage")
