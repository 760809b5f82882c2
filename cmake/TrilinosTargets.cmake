# Wraps Debian's Trilinos 13.2 packages in INTERFACE targets (bc::<Pkg>).
# The umbrella find_package(Trilinos COMPONENTS ...) fails on this build, and 13.2 has no
# <Pkg>::all_libs targets, so each package is found on its own and its variables wrapped.
function(bc_trilinos_package pkg)
  find_package(${pkg} REQUIRED)
  add_library(bc_${pkg} INTERFACE)
  # SYSTEM: warnings stay on for our code only.
  target_include_directories(bc_${pkg} SYSTEM INTERFACE ${${pkg}_INCLUDE_DIRS} ${${pkg}_TPL_INCLUDE_DIRS})
  target_link_libraries(bc_${pkg} INTERFACE ${${pkg}_LIBRARIES} ${${pkg}_TPL_LIBRARIES} MPI::MPI_CXX)
  add_library(bc::${pkg} ALIAS bc_${pkg})
endfunction()

foreach(pkg Teuchos Sacado Tpetra Belos Amesos2 Ifpack2)
  bc_trilinos_package(${pkg})
endforeach()
