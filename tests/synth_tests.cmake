# Tests of the synthetic-scene pieces (scene/, shadow/). Include from tests/CMakeLists.txt
# and add the list to the test executable; they need penumbra_shadow (which brings
# penumbra_scene, penumbra_raster and glm) and GTest::gtest_main.
set(PENUMBRA_SYNTH_TEST_SOURCES
    ${CMAKE_SOURCE_DIR}/scene/patch_mesh_test.cpp
    ${CMAKE_SOURCE_DIR}/shadow/intensity_transfer_test.cpp
    ${CMAKE_SOURCE_DIR}/shadow/light_frustum_test.cpp)
