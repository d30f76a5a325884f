# make test's wheel (tests/python): scikit-build-core packs what a plain build in
# LEVER_PYTHON_PREBUILT already compiled (the module for its Python, the `lever` command) with the
# package's Python files, compiling nothing: the wheel is installed into a fresh virtual
# environment and the Python tests run against it. `pip wheel .` without it builds from source.
set(_built "${LEVER_PYTHON_PREBUILT}")
file(GLOB _lever_module "${_built}/python/lever/_lever*.so")
if(NOT _lever_module OR NOT EXISTS "${_built}/tools/lever/lever")
  message(FATAL_ERROR "lever: LEVER_PYTHON_PREBUILT=${_built} holds no built Python module or "
                      "lever command (build the targets lever_python and lever_cli there first)")
endif()
install(FILES ${_lever_module} DESTINATION lever COMPONENT python)
install(FILES python/lever/__init__.py python/lever/mujoco.py python/lever/_mujoco_names.py
  python/lever/_command.py DESTINATION lever COMPONENT python)
install(PROGRAMS "${_built}/tools/lever/lever" DESTINATION lever/bin COMPONENT python)
# the targets pyproject.toml asks scikit-build-core to build: nothing to do here
add_custom_target(lever_python)
add_custom_target(lever_cli)
