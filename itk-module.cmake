# The module's description, dependencies and test dependencies, read by ITK's module
# system (in-tree and build-tree builds) and by CMake/SmallIsoComponentInstalledITK.cmake
# (builds against an installed ITK).
set(DOCUMENTATION "Removes the small connected components (specks and bubbles) that noise
puts on either side of an isovalue, by changing only the samples that create them, so that
an isosurface extracted afterwards has no tiny pieces.")

itk_module(SmallIsoComponent
  ENABLE_SHARED
  DEPENDS
    ITKCommon
  TEST_DEPENDS
    ITKTestKernel
    ITKGoogleTest
    ITKIOMeta
    ITKIONRRD
  DESCRIPTION
    "${DOCUMENTATION}"
  EXCLUDE_FROM_DEFAULT
)
