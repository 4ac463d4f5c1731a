# The Python module (python/, docs/python.md): on by default when Python 3 with its headers,
# numpy and pybind11 are found (Debian python3-dev, python3-numpy, pybind11-dev).
#
# Debian's numpy and pybind11 belong to /usr/bin/python3; a python3 earlier on PATH (pyenv,
# a venv without numpy) would make the module silently vanish, so /usr/bin/python3 is
# preferred when it exists. Pass -DPython3_EXECUTABLE=... to choose another.
#
# Not with QUACK_SANITIZE or QUACK_TSAN: a sanitizer build cannot be loaded into an
# interpreter that was not itself built with it (the runtime must come first in the process).
set(quack_python_default OFF)
if(NOT QUACK_SANITIZE AND NOT QUACK_TSAN AND QUACK_BUILD_IO)
  if(NOT DEFINED Python3_EXECUTABLE AND EXISTS /usr/bin/python3)
    set(Python3_EXECUTABLE /usr/bin/python3)
  endif()
  find_package(Python3 3.8 QUIET COMPONENTS Interpreter Development.Module NumPy)
  if(Python3_FOUND)
    find_package(pybind11 2.6 CONFIG QUIET)
  endif()
  if(Python3_FOUND AND pybind11_FOUND)
    set(quack_python_default ON)
  endif()
endif()
option(QUACK_BUILD_PYTHON "Build the Python module (pybind11, numpy)" ${quack_python_default})
if(QUACK_BUILD_PYTHON)
  if(QUACK_SANITIZE)
    message(FATAL_ERROR "QUACK_BUILD_PYTHON: not with QUACK_SANITIZE (an ASan module cannot load "
                        "into an interpreter built without it); see docs/python.md")
  endif()
  if(NOT QUACK_BUILD_IO)
    message(FATAL_ERROR "QUACK_BUILD_PYTHON needs QUACK_BUILD_IO (scene and state files)")
  endif()
  if(NOT Python3_FOUND OR NOT pybind11_FOUND)
    # Asked for explicitly: say what is missing.
    find_package(Python3 3.8 REQUIRED COMPONENTS Interpreter Development.Module NumPy)
    find_package(pybind11 2.6 CONFIG REQUIRED)
  endif()
  message(STATUS "Quack: Python module for ${Python3_EXECUTABLE} (${Python3_VERSION})")
else()
  message(STATUS "Quack: no Python module (QUACK_BUILD_PYTHON off; docs/python.md)")
endif()
