"""The outputs: datasets for figures, tables, the checks against the paper and against the committed
figure references, and the plots.  Built on every layer below."""
