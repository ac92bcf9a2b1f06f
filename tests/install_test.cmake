# `cmake --install` into a temporary prefix installs qmaps, qmaps-plot and the Python package qmaps
# with its engine, and each works from there. Run as: cmake -DBUILD_DIR=... -DPYTHON_DIR=... -P install_test.cmake
set(prefix "${BUILD_DIR}/install-test")
file(REMOVE_RECURSE "${prefix}")
execute_process(COMMAND "${CMAKE_COMMAND}" --install "${BUILD_DIR}" --prefix "${prefix}"
                RESULT_VARIABLE status OUTPUT_QUIET)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "cmake --install failed: ${status}")
endif()
foreach(file bin/qmaps bin/qmaps-plot "${PYTHON_DIR}/qmaps/__init__.py" "${PYTHON_DIR}/qmaps/runfile.py"
             "${PYTHON_DIR}/qmaps/plot.py")
  if(NOT EXISTS "${prefix}/${file}")
    message(FATAL_ERROR "not installed: ${file}")
  endif()
endforeach()
execute_process(COMMAND "${prefix}/bin/qmaps" --version OUTPUT_VARIABLE version RESULT_VARIABLE status)
if(NOT status EQUAL 0 OR NOT version MATCHES "^qmaps ")
  message(FATAL_ERROR "the installed qmaps does not run: ${status} ${version}")
endif()
execute_process(COMMAND "${prefix}/bin/qmaps-plot" --help OUTPUT_QUIET RESULT_VARIABLE status)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "the installed qmaps-plot does not run: ${status}")
endif()
execute_process(COMMAND "${CMAKE_COMMAND}" -E env "PYTHONPATH=${prefix}/${PYTHON_DIR}"
                        /usr/bin/python3 -c "import qmaps; print(len(qmaps.maps()), qmaps.__file__)"
                OUTPUT_VARIABLE where RESULT_VARIABLE status)
if(NOT status EQUAL 0 OR NOT where MATCHES "^[1-9][0-9]* .*install-test")
  message(FATAL_ERROR "the installed package does not import with its engine: ${status} ${where}")
endif()
file(REMOVE_RECURSE "${prefix}")
message(STATUS "installed and ran: ${version}")
