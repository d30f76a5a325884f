# cmake -DSOURCE=<repo> -DBINARY=<dir> -P build_wasm.cmake: configure (once) and build lever_wasm
# with Emscripten into BINARY, as `make web` does into build-web/. The web tests' fixture.
set(ENV{NODE_PATH} /usr/share/nodejs)  # Emscripten's JS optimizer needs Debian's node-acorn
if(NOT EXISTS ${BINARY}/CMakeCache.txt)
  execute_process(COMMAND emcmake ${CMAKE_COMMAND} -S ${SOURCE} -B ${BINARY}
      -DCMAKE_BUILD_TYPE=Release -DLEVER_BUILD_TESTS=OFF -DLEVER_BUILD_TOOLS=OFF
      -DLEVER_BUILD_BENCH=OFF -DLEVER_WITH_MUJOCO=OFF
    RESULT_VARIABLE status)
  if(NOT status EQUAL 0)
    file(REMOVE ${BINARY}/CMakeCache.txt)
    message(FATAL_ERROR "configuring the WebAssembly build failed")
  endif()
endif()
execute_process(COMMAND ${CMAKE_COMMAND} --build ${BINARY} --target lever_wasm -j 2
  RESULT_VARIABLE status)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "building lever_wasm failed")
endif()
