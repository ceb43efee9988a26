"""The repository names no package registry and downloads from no hard-coded address.

The machines reach Debian's archive, PyPI and the npm registry only through the apt and pip
configuration they already have, so a host name written into the tree is at best dead and at
worst a download that bypasses that configuration. The registries' host names are assembled
from pieces below so that this file does not itself contain them.
"""
import os
import re
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]

# Second-level names of the registries and their archives, joined with their top-level domain.
_REGISTRY_HOSTS = [name + '.' + tld for name, tld in (
    ('debian', 'org'), ('pypi', 'org'), ('pythonhosted', 'org'), ('pypi', 'python.org'),
    ('npmjs', 'org'), ('npmjs', 'com'), ('yarnpkg', 'com'), ('ubuntu', 'com'), ('ros', 'org'),
    ('packages.ros', 'org'))]
_REGISTRY = re.compile('|'.join(r'(^|[^a-z0-9-])' + re.escape(h) for h in _REGISTRY_HOSTS), re.IGNORECASE)
# Addresses a tracked file may contain: the local master of tests and a source repository.
_URL = re.compile(r'\b[a-z][a-z0-9+.-]*://([^/\s)"\'>:]+)', re.IGNORECASE)
_ALLOWED_URL_HOSTS = {'127.0.0.1', 'localhost', 'github.com'}


# Not in git: the build workspace, make test-compat's chroot, the demo's output.
_UNTRACKED_DIRS = {'.git', '.ws', '.compat', 'demo_output', '__pycache__'}


def _git(*args):
    try:
        return subprocess.run(('git',) + args, cwd=REPO, check=True, stdout=subprocess.PIPE,
                              stderr=subprocess.DEVNULL).stdout
    except (OSError, subprocess.CalledProcessError):
        return None  # no git, or a copy of the tree (make test-compat's chroot)


def _tree_files():
    listed = _git('ls-files', '-z')
    if listed is not None:
        return listed.decode().split('\0')
    names = []
    for top, dirs, files in os.walk(REPO):
        dirs[:] = [d for d in dirs if d not in _UNTRACKED_DIRS]
        names += [os.path.relpath(os.path.join(top, f), REPO) for f in files]
    return names


def _tracked_text_files():
    for name in _tree_files():
        path = REPO / name
        if not name or not path.is_file():
            continue
        data = path.read_bytes()
        if b'\0' in data[:8192]:
            continue  # binary (pictures, fuzz inputs)
        yield name, data.decode('utf-8', 'replace')


def test_no_registry_host_is_named():
    # The lines of a file that holds a host name anywhere (a plain substring search of its lower
    # case): the pattern over every line of every file took 9 s.
    def may_name_one(text):
        lower = text.lower()
        return any(host in lower for host in _REGISTRY_HOSTS)
    found = ['%s:%d: %s' % (name, number, line.strip())
             for name, text in _tracked_text_files() if may_name_one(text)
             for number, line in enumerate(text.splitlines(), 1) if _REGISTRY.search(line)]
    assert not found, 'registry host names in the tree:\n' + '\n'.join(found)


def test_no_address_other_than_local_ones_and_source_repositories():
    found = ['%s:%d: %s' % (name, number, match.group(0))
             for name, text in _tracked_text_files()
             for number, line in enumerate(text.splitlines(), 1)
             for match in _URL.finditer(line) if match.group(1).lower() not in _ALLOWED_URL_HOSTS]
    assert not found, 'hard-coded addresses in the tree:\n' + '\n'.join(found)


def test_no_commit_message_names_a_registry_host():
    log = _git('log', '--format=%H %B')
    if log is None:
        pytest.skip('not a git checkout: no commit messages to read')
    log = log.decode('utf-8', 'replace')
    found = [line for line in log.splitlines() if _REGISTRY.search(line)]
    assert not found, 'commit messages naming registry hosts:\n' + '\n'.join(found)
