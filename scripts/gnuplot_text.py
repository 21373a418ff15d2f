"""gnuplot_text — a file name as a gnuplot string, for the chart scripts.

In single quotes gnuplot takes every character as it is, except the single
quote itself, written twice; in double quotes it would read a backslash as
an escape. So `quoted` gives paths under folders such as /home/o'brien, or
holding a backslash, to gnuplot unchanged (tb_chart_paths.sh)."""


def quoted(path):
    """path as a single-quoted gnuplot string."""
    return "'" + str(path).replace("'", "''") + "'"
