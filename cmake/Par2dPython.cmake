# Finds what the Python module and the Python-based tests need; sets PAR2D_BUILD_PYTHON's default.
# Found (pybind11, and a Python 3 with NumPy and pytest) -> the module is built and tested by
# ctest. The README's install command installs all of it, so CI always builds and runs them.
# The first python3 in PATH that has NumPy and pytest, else Debian's /usr/bin/python3 (where
# apt's python3-* packages go) when another python3 (pyenv, conda) comes first and lacks them.
if(NOT Python3_EXECUTABLE)
  find_program(PAR2D_PYTHON_IN_PATH NAMES python3)
  foreach(candidate ${PAR2D_PYTHON_IN_PATH} /usr/bin/python3)
    if(EXISTS "${candidate}")
      execute_process(COMMAND ${candidate} -c "import numpy, pytest" RESULT_VARIABLE rc OUTPUT_QUIET ERROR_QUIET)
      if(rc EQUAL 0)
        set(Python3_EXECUTABLE ${candidate})
        break()
      endif()
    endif()
  endforeach()
endif()
find_package(Python3 COMPONENTS Interpreter Development.Module)
find_package(pybind11 CONFIG QUIET)

function(par2d_python_has modules result)
  set(${result} OFF PARENT_SCOPE)
  if(Python3_Interpreter_FOUND)
    execute_process(COMMAND ${Python3_EXECUTABLE} -c "import ${modules}"
      RESULT_VARIABLE rc OUTPUT_QUIET ERROR_QUIET)
    if(rc EQUAL 0)
      set(${result} ON PARENT_SCOPE)
    endif()
  endif()
endfunction()

par2d_python_has("numpy, pytest" PAR2D_PYTHON_HAS_TEST_MODULES)
par2d_python_has("matplotlib" PAR2D_PYTHON_HAS_MATPLOTLIB)
if(PAR2D_SANITIZE)
  # An instrumented module cannot be loaded into Debian's uninstrumented interpreter.
  set(PAR2D_BUILD_PYTHON_DEFAULT OFF)
  message(STATUS "par2d: Python module not built in a sanitizer build (PAR2D_SANITIZE=${PAR2D_SANITIZE})")
elseif(pybind11_FOUND AND Python3_Development.Module_FOUND AND PAR2D_PYTHON_HAS_TEST_MODULES)
  set(PAR2D_BUILD_PYTHON_DEFAULT ON)
else()
  set(PAR2D_BUILD_PYTHON_DEFAULT OFF)
  message(STATUS "par2d: Python module not built (needs pybind11-dev, python3-dev, python3-numpy, "
                 "python3-pytest for ${Python3_EXECUTABLE}); set Python3_EXECUTABLE to choose another Python")
endif()
option(PAR2D_BUILD_PYTHON "Build the Python module `par2d` and its pytest suite" ${PAR2D_BUILD_PYTHON_DEFAULT})
if(PAR2D_BUILD_PYTHON AND NOT PAR2D_BUILD_PYTHON_DEFAULT AND NOT PAR2D_SANITIZE)
  message(FATAL_ERROR "PAR2D_BUILD_PYTHON is ON but pybind11, the Python headers, NumPy or pytest are missing "
                      "for ${Python3_EXECUTABLE}")
endif()
