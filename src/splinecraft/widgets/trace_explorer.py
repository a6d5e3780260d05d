"""placeholder"""
class TraceExplorer:  # pragma: no cover
    pass
