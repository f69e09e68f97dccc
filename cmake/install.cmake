# Install rules (`cmake --install build --prefix P`; DEVELOPERS.md "Install"):
#   P/bin/deepcontact
#   P/lib/libdc_*.a and P/include/dc/<lib>/*.hpp         the libraries and their public headers
#   P/lib/cmake/DeepContact/                              find_package(DeepContact) →
#                                                         DeepContact::core … DeepContact::research
#   P/share/deepcontact/{models,scenes,bench/plots,research/plots,python/deepcontact}
#                                                         the data root of dc::data_path
#   P/share/doc/deepcontact/                              README, DEVELOPERS, docs/, examples/
# Nothing installed names the source or build tree, so P can be moved.
include(CMakePackageConfigHelpers)

set(DC_INSTALLED_LIBRARIES dc_core dc_sph dc_io dc_lcp dc_engine dc_warmstart dc_learning dc_cnn dc_bench dc_research)
foreach(lib ${DC_INSTALLED_LIBRARIES})
  string(REPLACE "dc_" "" short ${lib})
  set_target_properties(${lib} PROPERTIES EXPORT_NAME ${short})
  get_target_property(dir ${lib} SOURCE_DIR)
  install(DIRECTORY ${dir}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endforeach()
# The INTERFACE targets of third-party libraries found without a CMake package (absolute
# Debian paths) travel with the export set.
set_target_properties(dc_hdf5 PROPERTIES EXPORT_NAME hdf5)
set_target_properties(dc_cholmod PROPERTIES EXPORT_NAME cholmod)
# A consumer must compile with the -march of the libraries (Eigen's object layout depends on
# the vector width, DEVELOPERS.md "Build") and without FP contraction (docs/reproducibility.md):
# the installed dc_core carries both flags to everything that links it.
if(DC_NATIVE AND NOT DC_FUZZ)
  target_compile_options(dc_core INTERFACE $<INSTALL_INTERFACE:-march=native>)
endif()
target_compile_options(dc_core INTERFACE $<INSTALL_INTERFACE:-ffp-contract=off>)

install(TARGETS ${DC_INSTALLED_LIBRARIES} dc_hdf5 dc_cholmod EXPORT DeepContactTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(TARGETS deepcontact RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(EXPORT DeepContactTargets NAMESPACE DeepContact:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/DeepContact)
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/DeepContactConfig.cmake.in
                              ${CMAKE_BINARY_DIR}/DeepContactConfig.cmake
                              INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/DeepContact)
write_basic_package_version_file(${CMAKE_BINARY_DIR}/DeepContactConfigVersion.cmake
                                 VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/DeepContactConfig.cmake ${CMAKE_BINARY_DIR}/DeepContactConfigVersion.cmake
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/DeepContact)

# The data root keeps the source tree's relative paths (dc::data_path("bench/plots/…")).
set(DC_DATA_DESTINATION ${CMAKE_INSTALL_DATADIR}/deepcontact)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/models ${PROJECT_SOURCE_DIR}/scenes DESTINATION ${DC_DATA_DESTINATION})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/bench/plots DESTINATION ${DC_DATA_DESTINATION}/bench)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/research/plots DESTINATION ${DC_DATA_DESTINATION}/research)
# render_trajectory.py run as a script reads trajectories with python/deepcontact/trajectory.py.
install(FILES ${PROJECT_SOURCE_DIR}/python/deepcontact/trajectory.py DESTINATION ${DC_DATA_DESTINATION}/python/deepcontact)
set(DC_DOC_DESTINATION ${CMAKE_INSTALL_DATAROOTDIR}/doc/deepcontact)
install(FILES ${PROJECT_SOURCE_DIR}/README.md ${PROJECT_SOURCE_DIR}/DEVELOPERS.md ${PROJECT_SOURCE_DIR}/LICENSE
        DESTINATION ${DC_DOC_DESTINATION})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/docs/ DESTINATION ${DC_DOC_DESTINATION}/docs)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/examples/ DESTINATION ${DC_DOC_DESTINATION}/examples)
