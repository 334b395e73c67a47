# The Python package (python/): built when pybind11 and an interpreter with numpy and its headers
# are found, unless -DHARMONIA_BUILD_PYTHON=OFF. The interpreter is -DPython_EXECUTABLE when given;
# else the first of `python3` on PATH and Debian's /usr/bin/python3 that can import numpy (another
# python3 may come first on PATH, e.g. pyenv's, without numpy). Configure says which it took.
option(HARMONIA_BUILD_PYTHON "Build the Python package (python/) when pybind11 and numpy are found" ON)

set(HARMONIA_PYTHON_FOUND FALSE)
if(HARMONIA_BUILD_PYTHON)
  # Whether an interpreter imports numpy and has the headers an extension module compiles against.
  set(harmonia_python_probe
      "import numpy, os, sysconfig; assert os.path.exists(os.path.join(sysconfig.get_paths()['include'], 'Python.h'))")
  if(NOT Python_EXECUTABLE)
    find_program(harmonia_python_on_path NAMES python3 NO_CACHE)
    foreach(candidate ${harmonia_python_on_path} /usr/bin/python3)
      if(EXISTS "${candidate}")
        execute_process(COMMAND "${candidate}" -c "${harmonia_python_probe}"
                        RESULT_VARIABLE probe_result OUTPUT_QUIET ERROR_QUIET)
        if(probe_result EQUAL 0)
          set(Python_EXECUTABLE "${candidate}" CACHE FILEPATH "The interpreter of the Python package")
          break()
        endif()
      endif()
    endforeach()
  endif()
  if(Python_EXECUTABLE)
    find_package(Python 3.8 COMPONENTS Interpreter Development.Module)
    set(PYBIND11_FINDPYTHON ON)
    find_package(pybind11 2.6 CONFIG QUIET)
  endif()
  if(Python_FOUND AND pybind11_FOUND)
    execute_process(COMMAND "${Python_EXECUTABLE}" -c "import numpy; print(numpy.__version__)"
                    OUTPUT_VARIABLE harmonia_numpy_version OUTPUT_STRIP_TRAILING_WHITESPACE
                    RESULT_VARIABLE numpy_result ERROR_QUIET)
  endif()
  if(Python_FOUND AND pybind11_FOUND AND numpy_result EQUAL 0)
    set(HARMONIA_PYTHON_FOUND TRUE)
    message(STATUS "harmonia: Python package for ${Python_EXECUTABLE} (Python ${Python_VERSION}, "
                   "numpy ${harmonia_numpy_version}, pybind11 ${pybind11_VERSION})")
  else()
    message(STATUS "harmonia: no Python package (needs pybind11 and an interpreter with numpy and "
                   "its headers: apt-get install pybind11-dev python3-dev python3-numpy, or "
                   "-DPython_EXECUTABLE=...)")
  endif()
endif()
