# Image metrics (design §4): mean / p99 / max 8-bit error, PSNR, SSIM (OpenCV contrib
# `quality`) and LDR-FLIP, for `penumbra compare` and the accuracy charts. Included from the
# top-level CMakeLists.txt rather than living in reference/CMakeLists.txt, which belongs to
# the ray-traced reference renderer, so the two merge without touching each other.
if(PENUMBRA_WITH_OPENCV)
  find_package(OpenCV REQUIRED COMPONENTS core imgproc imgcodecs quality)
  add_library(penumbra_metrics STATIC ${CMAKE_CURRENT_LIST_DIR}/image_metrics.cpp
                                      ${CMAKE_CURRENT_LIST_DIR}/flip.cpp
                                      ${CMAKE_CURRENT_LIST_DIR}/shadow_region.cpp)
  target_link_libraries(penumbra_metrics PUBLIC penumbra_core ${OpenCV_LIBS} nlohmann_json::nlohmann_json)
  target_include_directories(penumbra_metrics SYSTEM PRIVATE ${OpenCV_INCLUDE_DIRS})
  # `penumbra accuracy` as a library function (reference/accuracy.h). Its ray-traced
  # reference comes from penumbra_reference, which reference/CMakeLists.txt adds after this
  # file exactly when penumbra_lighting exists (Embree); a link to a target defined later
  # is resolved when CMake generates.
  # `penumbra tune` (reference/settings_tuning.h) measures candidates the same way.
  add_library(penumbra_accuracy STATIC ${CMAKE_CURRENT_LIST_DIR}/accuracy.cpp
                                       ${CMAKE_CURRENT_LIST_DIR}/settings_tuning.cpp)
  target_link_libraries(penumbra_accuracy PUBLIC penumbra_metrics penumbra_shadow penumbra_scene
                                                 penumbra_hdr)
  target_include_directories(penumbra_accuracy SYSTEM PRIVATE ${OpenCV_INCLUDE_DIRS})
  if(PENUMBRA_WITH_EMBREE AND TARGET penumbra_lighting)
    target_link_libraries(penumbra_accuracy PRIVATE penumbra_reference)
    target_compile_definitions(penumbra_accuracy PRIVATE PENUMBRA_HAVE_REFERENCE=1)
  endif()
endif()
