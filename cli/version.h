/* version.h — the one project version every tool prints with --version
 * (and records in its outputs), with the git commit it was built from and
 * whether the tree had uncommitted changes to tracked files then; the
 * Makefile passes RTSIM_GIT and RTSIM_GIT_DIRTY (1, 0; -1 = unknown) to every
 * cli/ object and rebuilds them when either changes (mk/version.mk). */
#ifndef RTSIM_CLI_VERSION_H
#define RTSIM_CLI_VERSION_H

#define RTSIM_VERSION "0.1.0"

#ifndef RTSIM_GIT
#define RTSIM_GIT "unknown"
#endif

#ifndef RTSIM_GIT_DIRTY
#define RTSIM_GIT_DIRTY (-1)
#endif

#endif
