# Wraps Debian's Trilinos 13.2 packages in imported INTERFACE targets (bc::<Pkg>). Installed with
# BeamContact and included by BeamContactConfig.cmake, so a project built against the install tree
# finds Trilinos the same way.
# The umbrella find_package(Trilinos COMPONENTS ...) fails on this build, and 13.2 has no
# <Pkg>::all_libs targets, so each package is found on its own and its variables wrapped.
if(NOT TARGET MPI::MPI_CXX)
  find_package(MPI REQUIRED COMPONENTS CXX)
endif()
function(bc_trilinos_package pkg)
  if(TARGET bc::${pkg})
    return()
  endif()
  find_package(${pkg} REQUIRED)
  add_library(bc::${pkg} INTERFACE IMPORTED GLOBAL)
  # Include directories of imported targets are SYSTEM: warnings stay on for our code only.
  set_target_properties(bc::${pkg} PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES "${${pkg}_INCLUDE_DIRS};${${pkg}_TPL_INCLUDE_DIRS}"
    INTERFACE_LINK_LIBRARIES "${${pkg}_LIBRARIES};${${pkg}_TPL_LIBRARIES};MPI::MPI_CXX")
endfunction()

foreach(pkg Teuchos Sacado Tpetra Belos Amesos2 Ifpack2 MueLu)
  bc_trilinos_package(${pkg})
endforeach()
