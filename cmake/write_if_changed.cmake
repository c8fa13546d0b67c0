# write_if_changed(FILE TEXT): writes TEXT to FILE unless FILE already holds it. A generated
# header keeps its timestamp when its text is the same, so regenerating it rebuilds nothing.
function(write_if_changed file text)
  set(current "")
  if(EXISTS ${file})
    file(READ ${file} current)
  endif()
  if(NOT current STREQUAL text)
    file(WRITE ${file} "${text}")
  endif()
endfunction()
