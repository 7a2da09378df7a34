# What `make install` and the Debian package hold: the binary, its man page, the README, the
# licenses and the demo scene that `omnishadow render` draws without arguments.
# scripts/package.sh configures a build with OMNISHADOW_DEMO_SCENE pointing at the installed
# scene and OMNISHADOW_MAN_PAGE at a page generated from --help, then runs CPack.
include(GNUInstallDirs)

set(OMNISHADOW_MAN_PAGE "" CACHE FILEPATH "omnishadow.1.gz to install (scripts/package.sh makes it)")
set(OMNISHADOW_PACKAGE_CONTACT "omnishadow maintainers <omnishadow@localhost>"
    CACHE STRING "The Debian package's Maintainer field")

install(TARGETS omnishadow RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
# The OpenImageIO plugin is dlopen'ed from ../lib/omnishadow beside the binary (oiio_plugin.h),
# not from the multiarch library folder GNUInstallDirs would pick. dpkg-shlibdeps reads its
# NEEDED entries too, so OpenImageIO's package lands in Depends.
install(TARGETS omnishadow_oiio LIBRARY DESTINATION lib/omnishadow)
install(FILES scenes/demo/room.gltf scenes/demo/room.lights.json
        DESTINATION ${CMAKE_INSTALL_DATADIR}/omnishadow/demo)
install(FILES README.md DESTINATION ${CMAKE_INSTALL_DOCDIR})
# The repository has no LICENSE file of its own yet; the one there is ships as the copyright.
if(EXISTS ${PROJECT_SOURCE_DIR}/LICENSE)
  install(FILES LICENSE DESTINATION ${CMAKE_INSTALL_DOCDIR} RENAME copyright)
endif()
if(OMNISHADOW_MAN_PAGE)
  install(FILES ${OMNISHADOW_MAN_PAGE} DESTINATION ${CMAKE_INSTALL_MANDIR}/man1)
endif()

set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME omnishadow)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_CONTACT "${OMNISHADOW_PACKAGE_CONTACT}")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "headless glTF renderer with omnidirectional point-light shadows")
set(CPACK_DEBIAN_PACKAGE_DESCRIPTION
    "Renders glTF 2.0 scenes without a display through EGL and OpenGL 4.5 (a GPU, or Mesa's\n software rasteriser), with shadowed point lights, AOVs and crash-proof batches.")
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)  # omnishadow_<version>_<arch>.deb
set(CPACK_DEBIAN_PACKAGE_SECTION graphics)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# glvnd's libEGL, which the binary links, needs a vendor library to find a device; Mesa's
# provides the software device, so that the package renders on any machine.
# libavif is loaded when a scene has AVIF textures, Embree when `verify` casts its rays (dlopen,
# which dpkg-shlibdeps cannot see).
set(CPACK_DEBIAN_PACKAGE_DEPENDS
    "libegl-mesa0 | libegl-vendor, libgl1-mesa-dri, ${OMNISHADOW_LIBAVIF_PACKAGE}, ${OMNISHADOW_LIBEMBREE_PACKAGE}")
set(CPACK_STRIP_FILES ON)
include(CPack)
