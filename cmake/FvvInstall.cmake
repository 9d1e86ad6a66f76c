# Installs the public headers and the fvv:: targets, with a package config so
# that find_package(fvv) works for embedding applications, and a pkg-config file.
include(CMakePackageConfigHelpers)
install(DIRECTORY include/fvv DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
# Exported as fvv::dec, fvv::codec, ... (the same names as the build-tree aliases).
foreach(t base codec_dec codec container_dec container dec)
  set_target_properties(fvv_${t} PROPERTIES EXPORT_NAME ${t})
endforeach()
install(TARGETS fvv_codec_dec fvv_codec fvv_base fvv_container_dec fvv_container fvv_dec EXPORT fvvTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
if(TARGET fvv)
  install(TARGETS fvv RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endif()
install(EXPORT fvvTargets NAMESPACE fvv:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/fvv)
# The encoder (fvv::encoder, C API in fvv_encoder.h) is the optional component
# "encoder": its static libraries need the capture front end's dependencies
# (Eigen, yaml-cpp, toml++, libpng, OpenEXR, nlohmann-json), which decoder-only
# applications should not have to install. find_package(fvv COMPONENTS encoder).
foreach(t encoder encode shape track capture atlas body imageio)
  set_target_properties(fvv_${t} PROPERTIES EXPORT_NAME ${t})
endforeach()
install(TARGETS fvv_encoder fvv_encode fvv_shape fvv_track fvv_capture fvv_atlas fvv_body fvv_imageio
        EXPORT fvvEncoderTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(EXPORT fvvEncoderTargets NAMESPACE fvv:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/fvv)
# The exporter (fvv::export, C API in fvv_export.h: glTF and BVH from an open
# decoder) is the optional component "export" (it needs libpng and nlohmann-json).
set_target_properties(fvv_export PROPERTIES EXPORT_NAME export)
install(TARGETS fvv_export EXPORT fvvExportTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(EXPORT fvvExportTargets NAMESPACE fvv:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/fvv)
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/fvvConfig.cmake.in [=[
@PACKAGE_INIT@
include(CMakeFindDependencyMacro)
find_dependency(Threads)
find_dependency(zstd)
find_dependency(glm)
include("${CMAKE_CURRENT_LIST_DIR}/fvvTargets.cmake")
foreach(component IN LISTS fvv_FIND_COMPONENTS)
  if(component STREQUAL "encoder")
    find_dependency(Eigen3)
    find_dependency(PNG)
    find_dependency(OpenEXR)
    find_dependency(PkgConfig)
    pkg_check_modules(TURBOJPEG REQUIRED IMPORTED_TARGET libturbojpeg)
    find_dependency(nlohmann_json)
    find_dependency(yaml-cpp)
    find_dependency(tomlplusplus)
    find_dependency(tinyxml2)
    if(@FVV_HAVE_OPENCV_DNN@)
      find_dependency(OpenCV COMPONENTS core imgproc dnn)
    endif()
    include("${CMAKE_CURRENT_LIST_DIR}/fvvEncoderTargets.cmake")
    set(fvv_encoder_FOUND TRUE)
  elseif(component STREQUAL "export")
    find_dependency(PNG)
    find_dependency(nlohmann_json)
    include("${CMAKE_CURRENT_LIST_DIR}/fvvExportTargets.cmake")
    set(fvv_export_FOUND TRUE)
  else()
    set(fvv_${component}_FOUND FALSE)
  endif()
endforeach()
check_required_components(fvv)
]=])
configure_package_config_file(${CMAKE_CURRENT_BINARY_DIR}/fvvConfig.cmake.in
                              ${CMAKE_CURRENT_BINARY_DIR}/fvvConfig.cmake
                              INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/fvv)
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/fvvConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/fvvConfig.cmake
              ${CMAKE_CURRENT_BINARY_DIR}/fvvConfigVersion.cmake
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/fvv)
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/fvv.pc
     "prefix=${CMAKE_INSTALL_PREFIX}\nlibdir=\${prefix}/${CMAKE_INSTALL_LIBDIR}\nincludedir=\${prefix}/${CMAKE_INSTALL_INCLUDEDIR}\n\nName: fvv\nDescription: free-viewpoint video codec SDK\nVersion: ${PROJECT_VERSION}\nLibs: -L\${libdir} -lfvv_dec -lfvv_container -lfvv_container_dec -lfvv_codec -lfvv_codec_dec -lfvv_base -lzstd\nCflags: -I\${includedir}\n")
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/fvv.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
