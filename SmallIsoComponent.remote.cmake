#-- # Grading Level Criteria Report
#-- EVALUATION DATE: 2026-12-02
#-- EVALUATORS: [<<NO EVALUATOR>>,<<NO EVALUATOR>>]
#--
#-- ## Compliance level 5 star (AKA ITK main modules, or remote modules that could become core modules)
#--   - [ ] Widespread community dependance
#--   - [X] Above 90% code coverage
#--   - [ ] CI dashboards and testing monitored rigorously
#--   - [X] Key API features are exposed in wrapping interface
#--   - [ ] All requirements of Levels 4,3,2,1
#--
#-- ## Compliance Level 4 star (Very high-quality code, perhaps small community dependance)
#--   - [X] Meets all ITK code style standards
#--   - [X] No external requirements beyond those needed by ITK proper
#--   - [ ] Builds and passes tests on all supported platforms within 1 month of each core tagged release
#--            - [ ] Windows Shared Library Build with Visual Studio
#--            - [ ] Mac with clang compiler
#--            - [X] Linux with gcc compiler
#--   - [ ] Active developer community dedicated to maintaining code-base
#--   - [X] 75% C0-code coverage demonstrated for testing suite
#--   - [ ] Continuous integration testing performed
#--   - [ ] All requirements of Levels 3,2,1
#--
#-- ## Compliance Level 3 star (Quality beta code)
#--   - [X] API | executable interface is considered mostly stable and feature complete
#--   - [X] 10% C0-code coverage demonstrated for testing suite
#--   - [X] Some tests exist and pass on at least some platform
#--   - [X] All requirements of Levels 2,1
#--
#-- ## Compliance Level 2 star (Alpha code feature API development or niche community/execution environment dependance )
#--   - [X] Compiles for at least 1 niche set of execution environments, and perhaps others
#--         (may depend on specific external tools like a java environment, or specific external libraries to work )
#--   - [X] All requirements of Levels 1
#--
#-- ## Compliance Level 1 star (Pre-alpha features under development and code of unknown quality)
#--   - [X] Code compiles on at least 1 platform
#--
#-- ## Compliance Level 0 star ( Code/Feature of known poor-quality or deprecated status )
#--   - [ ] Code reviewed and explicitly identified as not recommended for use
#--
#-- ### Please document here any justification for the criteria above
#--       Style: ITK's .clang-format, checked by scripts/check-format.sh and the clang-format
#--       linter workflow; ITK's idioms (macros, PrintSelf, exceptions, static_assert).
#--       The module depends on ITKCommon only; VTK is optional and used by the
#--       command-line tools alone. Wrapped: the filter for every wrapped scalar type, its
#--       statistics and removed mask, and SmallIsoComponentEnums, with Python tests.
#--       Linux with GCC 12: builds and passes its tests against ITK 5.2.1 (Debian's, and
#--       built from source with the Python wrapping) and against ITK versions built from
#--       source by scripts/itk-from-source.sh (the README's compatibility table says which
#--       versions and paths). Windows and macOS have not been built yet, and the CI
#--       workflows in .github/workflows have not run yet, so level 4 is not claimed. Line
#--       coverage of include/ and src/ over the whole test suite: 98.2 % (scripts/coverage.sh).

itk_fetch_module(SmallIsoComponent
  "Removes the small connected components that noise leaves on either side of an
isovalue (specks of voxels >= S outside an object, bubbles of voxels < S inside it) by
changing only the voxels of those components, each to the mean of the nearest values on
the other side along the axes, so that an isosurface extracted afterwards (Marching Cubes,
Flying Edges) has no tiny pieces while every other voxel keeps its value bit for bit.
itk::SmallIsoComponentImageFilter takes scalar images of two or more dimensions, labels
both sides at once with a parallel union-find over scanline runs, returns a mask of the
changed voxels and per-side component statistics, and gives the same result for any
number of threads."
  MODULE_COMPLIANCE_LEVEL 3
  # Where the module is published.
  GIT_REPOSITORY https://github.com/SmallIsoComponent/ITKSmallIsoComponent.git
  # ITK pins a commit hash here when it adds the module.
  GIT_TAG main
  )
