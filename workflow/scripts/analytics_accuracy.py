"""Accuracy of the located critical and grazing points against resolution and cost."""
import logging

from vibroimpact import plotting
from vibroimpact.datasets import provenance, write_netcdf
from vibroimpact.workprecision import analytics_accuracy

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
ds = analytics_accuracy()
ds.attrs.update(provenance())
write_netcdf(ds, snakemake.output.nc)
plotting.save(plotting.fig_analytics_accuracy(ds), snakemake.output.pdf.removesuffix(".pdf"))
