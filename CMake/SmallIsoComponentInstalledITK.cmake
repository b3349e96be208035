# Builds the module against an installed ITK (such as Debian's libinsighttoolkit5-dev),
# which ships ITKConfig.cmake but not ITK's module-building CMake files.
#
# It provides small stand-ins for the ITK module macros that this module's
# itk-module.cmake, src/CMakeLists.txt and test/CMakeLists.txt use, so that those files
# are the same on every build path.

# Read the dependency lists from itk-module.cmake instead of repeating them here.
macro(itk_module _name)
  set(itk-module ${_name})
  set(_sic_mode "")
  foreach(_arg ${ARGN})
    if(_arg MATCHES "^(DEPENDS|PRIVATE_DEPENDS|COMPILE_DEPENDS|TEST_DEPENDS|DESCRIPTION|FACTORY_NAMES)$")
      set(_sic_mode ${_arg})
    elseif(_arg MATCHES "^(ENABLE_SHARED|EXCLUDE_FROM_DEFAULT)$")
      set(_sic_mode "")
    elseif(_sic_mode MATCHES "DEPENDS$")
      list(APPEND ${_name}_${_sic_mode} ${_arg})
    endif()
  endforeach()
endmacro()
include(${CMAKE_CURRENT_SOURCE_DIR}/itk-module.cmake)

set(_sic_itk_modules ${${itk-module}_DEPENDS} ${${itk-module}_PRIVATE_DEPENDS}
  ${${itk-module}_COMPILE_DEPENDS} ${SmallIsoComponent_APP_ITK_MODULES})
include(CTest)
if(BUILD_TESTING)
  list(APPEND _sic_itk_modules ${${itk-module}_TEST_DEPENDS})
endif()
# Debian's ITKGoogleTest entry has no library; the system GoogleTest provides it.
list(REMOVE_ITEM _sic_itk_modules ITKGoogleTest)
list(REMOVE_DUPLICATES _sic_itk_modules)
find_package(ITK REQUIRED COMPONENTS ${_sic_itk_modules})
include(${CMAKE_CURRENT_LIST_DIR}/SmallIsoComponentUseITK.cmake)
smalliso_use_itk()
# ITK's headers are not ours to keep warning-free.
include_directories(SYSTEM ${ITK_INCLUDE_DIRS})

if(NOT DEFINED BUILD_SHARED_LIBS)
  set(BUILD_SHARED_LIBS OFF)
endif()
set(CMAKE_CXX_STANDARD 17)
set(CMAKE_CXX_STANDARD_REQUIRED ON)
set(ITK_TEST_OUTPUT_DIR ${CMAKE_BINARY_DIR}/Testing/Temporary)
file(MAKE_DIRECTORY ${ITK_TEST_OUTPUT_DIR})

function(itk_module_add_library _name)
  add_library(${_name} ${ARGN})
  include(GenerateExportHeader)
  generate_export_header(${_name}
    EXPORT_MACRO_NAME ${_name}_EXPORT
    EXPORT_FILE_NAME ${CMAKE_BINARY_DIR}/include/${_name}Export.h)
  target_include_directories(${_name} PUBLIC
    $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/include>
    $<BUILD_INTERFACE:${CMAKE_BINARY_DIR}/include>)
  target_link_libraries(${_name} PUBLIC ${SmallIsoComponent_ITK_LINK_LIBRARIES})
  target_compile_options(${_name} PRIVATE ${SmallIsoComponent_WARNING_FLAGS})
endfunction()

macro(itk_module_test)
  set(${itk-module}-Test_LIBRARIES ${itk-module} ${SmallIsoComponent_ITK_LINK_LIBRARIES})
endmacro()

# A test driver in ITK's style: one executable that runs each test function by name,
# with ITK's --compare and related options.
macro(CreateTestDriver _kit _kit_libs _kit_tests)
  set(CMAKE_TESTDRIVER_BEFORE_TESTMAIN "#include \"itkTestDriverBeforeTest.inc\"")
  set(CMAKE_TESTDRIVER_AFTER_TESTMAIN "#include \"itkTestDriverAfterTest.inc\"")
  create_test_sourcelist(_sic_driver_sources ${_kit}TestDriver.cxx ${_kit_tests}
    EXTRA_INCLUDE itkTestDriverIncludeRequiredIOFactories.h
    FUNCTION ProcessArgumentsAndRegisterRequiredFactories)
  add_executable(${_kit}TestDriver ${_sic_driver_sources} ${ARGN})
  target_link_libraries(${_kit}TestDriver ${_kit_libs})
  target_compile_options(${_kit}TestDriver PRIVATE ${SmallIsoComponent_WARNING_FLAGS})
endmacro()

find_package(GTest REQUIRED)
include(GoogleTest)
macro(CreateGoogleTestDriver _kit _kit_libs _kit_tests)
  add_executable(${_kit}GTestDriver ${_kit_tests})
  target_link_libraries(${_kit}GTestDriver ${_kit_libs} GTest::gtest GTest::gtest_main)
  target_compile_options(${_kit}GTestDriver PRIVATE ${SmallIsoComponent_WARNING_FLAGS})
  gtest_discover_tests(${_kit}GTestDriver DISCOVERY_TIMEOUT 120 PROPERTIES LABELS ${itk-module})
endmacro()

include(ExternalData)
# Baselines are real files committed under test/; no object store is ever fetched from.
set(ExternalData_OBJECT_STORES ${CMAKE_BINARY_DIR}/ExternalData/Objects)
function(itk_add_test)
  ExternalData_add_test(ITKData ${ARGN})
  if("${ARGV0}" STREQUAL "NAME")
    set_property(TEST ${ARGV1} APPEND PROPERTY LABELS ${itk-module})
  endif()
endfunction()

add_subdirectory(src)
if(BUILD_TESTING)
  add_subdirectory(test)
  ExternalData_Add_Target(ITKData)
endif()
