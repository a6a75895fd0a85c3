"""What a user drives: the geompm command (run, validate, info, plot, study, bench), the library call
geompm.run, run folders, restarts, refusals of bad input, file safety and the commands the docs print."""
