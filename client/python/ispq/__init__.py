# SPDX-License-Identifier: Apache-2.0
"""Python client of the ispq quantization service.

    import ispq
    with ispq.Client("127.0.0.1:50051") as client:
        result = client.quantize("part.tmesh.json", level=25, on_progress=print)
    print(result.objective, result.valid, len(result.q))

`Client` covers every call of the service (proto/ispq/v1/service.proto); `load_tmesh` reads
.tmesh.json and .tmesh.pb files; failures raise `IspqError` with the gRPC code and the server's
message. The messages and stubs (`ispq.v1`) are generated from proto/ when the package is built.
"""
import pkgutil

# ispq.v1 is generated at build time: by pip into the installed package, by CMake into the build
# tree (build/<preset>/python/ispq/v1), which this makes importable next to the sources.
__path__ = pkgutil.extend_path(__path__, __name__)

from ispq.errors import IspqError  # noqa: E402
from ispq.progress import Progress  # noqa: E402
from ispq.results import QuantizeResult  # noqa: E402
from ispq.tmesh_files import load_tmesh  # noqa: E402
from ispq.client import Client  # noqa: E402
from ispq.batch import BatchEntry, plan_batch, run_batch  # noqa: E402

__all__ = ["BatchEntry", "Client", "IspqError", "Progress", "QuantizeResult", "load_tmesh",
           "plan_batch", "run_batch"]
