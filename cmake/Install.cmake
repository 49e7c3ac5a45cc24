# What `cmake --install` puts under the prefix for other projects (docs/package.md):
#   include/lixel/{solver,kit,codec,client,v1}                     public headers
#   lib/liblixel_{solver,kit,codec,proto,client,client_gl}.a         the libraries (codec: -lzstd -lz)
#   share/lixel/glsl/lixel_shadows.glsl                              the client shader kit
#   lib/cmake/lixel/lixelConfig.cmake (+ Version, Targets)           find_package(lixel CONFIG)
#   lib/pkgconfig/lixel.pc                                           pkg-config --cflags --libs lixel
#   share/lixel/proto/lixel/v1/lixel.proto                           the wire, for other languages
# Imported targets: lixel::solver (Eigen), lixel::kit (the shader kit's data), lixel::proto
# (protobuf, gRPC), lixel::client (both), lixel::client_gl (the kit's block and atlas on a GL
# context, through the caller's GL loader: no GL library); lixel_GLSL_DIR names the kit's folder.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(LIXEL_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/lixel)

# lixel::warnings is a private, compile-only dependency, but a static library's private links
# are part of its exported link interface: it goes in the export set (it adds no link items).
set_target_properties(lixel_warnings PROPERTIES EXPORT_NAME warnings)
set_target_properties(lixel_solver PROPERTIES EXPORT_NAME solver)
set_target_properties(lixel_kit PROPERTIES EXPORT_NAME kit)
set_target_properties(lixel_codec PROPERTIES EXPORT_NAME codec)
set_target_properties(lixel_proto PROPERTIES EXPORT_NAME proto)
set_target_properties(lixel_client PROPERTIES EXPORT_NAME client)
set_target_properties(lixel_client_gl PROPERTIES EXPORT_NAME client_gl)
install(TARGETS lixel_warnings lixel_solver lixel_kit lixel_codec lixel_proto lixel_client lixel_client_gl
        EXPORT lixelTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/solver/include/lixel/solver
                  ${PROJECT_SOURCE_DIR}/kit/include/lixel/kit
                  ${PROJECT_SOURCE_DIR}/codec/include/lixel/codec
                  ${PROJECT_SOURCE_DIR}/client/include/lixel/client
                  ${PROJECT_SOURCE_DIR}/client/gl/include/lixel/client
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/lixel
        FILES_MATCHING PATTERN "*.h")
set(lixel_generated ${PROJECT_BINARY_DIR}/proto/generated/lixel/v1)
install(FILES ${lixel_generated}/lixel.pb.h ${lixel_generated}/lixel.grpc.pb.h
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/lixel/v1)
install(FILES ${PROJECT_SOURCE_DIR}/proto/lixel/v1/lixel.proto
        DESTINATION ${CMAKE_INSTALL_DATADIR}/lixel/proto/lixel/v1)
set(LIXEL_INSTALL_GLSLDIR ${CMAKE_INSTALL_DATADIR}/lixel/glsl)
install(FILES ${PROJECT_SOURCE_DIR}/kit/glsl/lixel_shadows.glsl DESTINATION ${LIXEL_INSTALL_GLSLDIR})

install(EXPORT lixelTargets NAMESPACE lixel:: DESTINATION ${LIXEL_INSTALL_CMAKEDIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/lixelConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/lixelConfig.cmake
                              INSTALL_DESTINATION ${LIXEL_INSTALL_CMAKEDIR}
                              PATH_VARS LIXEL_INSTALL_GLSLDIR)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/lixelConfigVersion.cmake
                                 VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/lixelConfig.cmake ${PROJECT_BINARY_DIR}/lixelConfigVersion.cmake
        DESTINATION ${LIXEL_INSTALL_CMAKEDIR})

# pkg-config: @ONLY keeps ${prefix}-relative paths for the .pc file itself.
configure_file(${PROJECT_SOURCE_DIR}/cmake/lixel.pc.in ${PROJECT_BINARY_DIR}/lixel.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/lixel.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
