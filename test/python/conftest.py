"""pytest configuration: the rostest checkers under test/ros need a master and are run by
rostest, not collected here."""
collect_ignore_glob = ['../ros/*']
