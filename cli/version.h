/* version.h — the one project version every tool prints with --version
 * (and records in its outputs), with the git commit it was built from;
 * the Makefile passes RTSIM_GIT to every cli/ object. */
#ifndef RTSIM_CLI_VERSION_H
#define RTSIM_CLI_VERSION_H

#define RTSIM_VERSION "0.1.0"

#ifndef RTSIM_GIT
#define RTSIM_GIT "unknown"
#endif

#endif
