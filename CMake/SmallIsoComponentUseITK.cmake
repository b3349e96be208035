# smalliso_use_itk(): after find_package(ITK ...), makes ITK usable by the targets of the
# calling directory and sets SmallIsoComponent_ITK_LINK_LIBRARIES to what they link for it.
#
# ITK 6 deprecates UseITK.cmake (ITK_USE_FILE), which sets directory-wide include paths and
# compile definitions, in favour of its interface libraries: itk_generate_factory_registration()
# writes the IO factory registration headers, and linking the interface libraries and the
# ITK::ITKImageIO meta-module brings the include paths and turns the registration on. ITK 5
# has only UseITK.cmake.
macro(smalliso_use_itk)
  if(ITK_VERSION_MAJOR GREATER_EQUAL 6)
    itk_generate_factory_registration()
    set(SmallIsoComponent_ITK_LINK_LIBRARIES ${ITK_INTERFACE_LIBRARIES})
    if(TARGET ITK::ITKImageIO)
      list(APPEND SmallIsoComponent_ITK_LINK_LIBRARIES ITK::ITKImageIO)
    endif()
  else()
    include(${ITK_USE_FILE})
    set(SmallIsoComponent_ITK_LINK_LIBRARIES ${ITK_LIBRARIES})
  endif()
endmacro()
