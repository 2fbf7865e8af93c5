# Install rules for running fqd as a service from an installed prefix: the live viewer with
# the npm files it loads (share/fq/web, where fqd looks by default), an example configuration,
# the systemd unit with this prefix's paths, and the docs the unit's Documentation= names.
#
#   <prefix>/share/fq/web/                      index.html, viewer.js, frame_decode.js and
#                                               node_modules/three (build/, the orbit controls,
#                                               the Draco decoder): what the page imports
#   <prefix>/share/doc/fq/examples/fqd.toml     configs/fqd.toml without its source-tree web_root
#   <prefix>/lib/systemd/system/fqd.service     packaging/fqd.service.in, ExecStart in <prefix>/bin
#   <prefix>/share/doc/fq/                      README.md, docs/*.md and their pictures
#
# node_modules comes from scripts/web-deps.sh (npm ci in web/; setup-deps.sh runs it). Without
# it the viewer's page is installed alone, and fqd's / says what is missing.
set(FQ_INSTALL_WEBDIR "${CMAKE_INSTALL_DATADIR}/fq/web")
set(three "${PROJECT_SOURCE_DIR}/web/node_modules/three")

install(FILES web/index.html web/viewer.js web/frame_decode.js DESTINATION "${FQ_INSTALL_WEBDIR}")
install(FILES "${three}/package.json" "${three}/LICENSE" DESTINATION "${FQ_INSTALL_WEBDIR}/node_modules/three" OPTIONAL)
install(DIRECTORY "${three}/build" DESTINATION "${FQ_INSTALL_WEBDIR}/node_modules/three" OPTIONAL
        FILES_MATCHING PATTERN "*.js")
install(DIRECTORY "${three}/examples/jsm/controls" DESTINATION "${FQ_INSTALL_WEBDIR}/node_modules/three/examples/jsm"
        OPTIONAL)
install(DIRECTORY "${three}/examples/jsm/libs/draco" DESTINATION "${FQ_INSTALL_WEBDIR}/node_modules/three/examples/jsm/libs"
        OPTIONAL PATTERN "gltf" EXCLUDE)
install(CODE "
  if(NOT EXISTS \"${three}/build/three.module.js\")
    message(WARNING \"fq: web/node_modules is missing: the viewer's page is installed without three.js \"
                    \"(run scripts/web-deps.sh, then install again)\")
  endif()")

# The example configuration: the viewer is found beside the installed fqd, so the source
# tree's relative web_root goes.
file(READ "${PROJECT_SOURCE_DIR}/configs/fqd.toml" example)
string(REGEX REPLACE "\nweb_root = [^\n]*" "\n# web_root: default, the viewer installed with fqd (<prefix>/share/fq/web)" example "${example}")
string(REPLACE "# fqd configuration: the default used by scripts/stream_demo.sh."
               "# fqd configuration, installed as an example: copy it to /etc/fq/fqd.toml and edit." example "${example}")
file(WRITE "${PROJECT_BINARY_DIR}/packaging/fqd.toml" "${example}")
install(FILES "${PROJECT_BINARY_DIR}/packaging/fqd.toml" DESTINATION "${CMAKE_INSTALL_DOCDIR}/examples")

# Written at install time: `cmake --install --prefix P` puts P's paths in the unit.
install(CODE "
  set(FQ_FQD_PATH \"\${CMAKE_INSTALL_PREFIX}/${CMAKE_INSTALL_BINDIR}/fqd\")
  set(FQ_DOC_PATH \"\${CMAKE_INSTALL_PREFIX}/${CMAKE_INSTALL_DOCDIR}\")
  configure_file(\"${PROJECT_SOURCE_DIR}/packaging/fqd.service.in\" \"${PROJECT_BINARY_DIR}/packaging/fqd.service\" @ONLY)")
install(FILES "${PROJECT_BINARY_DIR}/packaging/fqd.service" DESTINATION lib/systemd/system)

file(GLOB fq_docs "${PROJECT_SOURCE_DIR}/docs/*.md" "${PROJECT_SOURCE_DIR}/docs/*.png")
install(FILES README.md ${fq_docs} DESTINATION "${CMAKE_INSTALL_DOCDIR}")
