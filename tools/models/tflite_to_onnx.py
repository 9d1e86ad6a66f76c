#!/usr/bin/python3
"""Converts a TensorFlow Lite model (a FlatBuffer, file identifier TFL3) into an
ONNX model that OpenCV 4.6's dnn module reads, for the few operators of
MediaPipe's pose detector and pose landmark models.

  tflite_to_onnx.py MODEL.tflite OUT.onnx [--input-name NAME]

The graph keeps TensorFlow Lite's semantics with ONNX's layout: every 4-D
tensor is NCHW in the ONNX graph (the input too: feed it N x 3 x H x W), and a
reshape of a 4-D tensor first turns it back to NHWC so elements keep their
order. Constant weights are folded: float16 (DEQUANTIZE) and sparse (DENSIFY)
tensors become dense float32 initialisers. Fused activations become Relu or
Clip. The graph is checked as opset 11; then each Clip's min and max move from
inputs to attributes (the opset 6 form), the only one OpenCV 4.6 reads.

The FlatBuffer is read with this file's own minimal table reader; the field
numbers are those of TensorFlow Lite's public schema (schema.fbs).
"""
import argparse
import struct
import sys

import numpy as np
import onnx
from onnx import helper, numpy_helper, TensorProto

# BuiltinOperator codes used here.
ADD, AVERAGE_POOL_2D, CONCATENATION, CONV_2D, DEPTHWISE_CONV_2D = 0, 1, 2, 3, 4
DEPTH_TO_SPACE, DEQUANTIZE, LOGISTIC, MAX_POOL_2D, MUL = 5, 6, 14, 17, 18
RELU, RELU6, RESHAPE, RESIZE_BILINEAR, PAD, PRELU, DENSIFY = 19, 21, 22, 23, 34, 54, 124
NAMES = {ADD: "ADD", AVERAGE_POOL_2D: "AVERAGE_POOL_2D", CONCATENATION: "CONCATENATION",
         CONV_2D: "CONV_2D", DEPTHWISE_CONV_2D: "DEPTHWISE_CONV_2D",
         DEPTH_TO_SPACE: "DEPTH_TO_SPACE", DEQUANTIZE: "DEQUANTIZE", LOGISTIC: "LOGISTIC",
         MAX_POOL_2D: "MAX_POOL_2D", MUL: "MUL", RELU: "RELU", RELU6: "RELU6",
         RESHAPE: "RESHAPE", RESIZE_BILINEAR: "RESIZE_BILINEAR", PAD: "PAD", PRELU: "PRELU",
         DENSIFY: "DENSIFY"}
# TensorType
FLOAT32, FLOAT16, INT32 = 0, 1, 2
# Padding, ActivationFunctionType
SAME, VALID = 0, 1
ACT_NONE, ACT_RELU, ACT_RELU6 = 0, 1, 3


class ConversionError(Exception):
    pass


class FlatBuffer:
    """Tables, vectors and scalars of a FlatBuffer, addressed by field number."""

    def __init__(self, data):
        self.b = data

    def _u(self, fmt, o):
        if o < 0 or o + struct.calcsize(fmt) > len(self.b):
            raise ConversionError(f"read outside the file at byte {o}")
        return struct.unpack_from("<" + fmt, self.b, o)[0]

    def root(self):
        if self.b[4:8] != b"TFL3":
            raise ConversionError("not a TensorFlow Lite model (no TFL3 identifier)")
        return self.table(self._u("I", 0))

    def table(self, o):
        vt = o - self._u("i", o)
        return (o, vt, (self._u("H", vt) - 4) // 2)

    def field(self, t, i):
        o, vt, n = t
        if i >= n:
            return None
        off = self._u("H", vt + 4 + 2 * i)
        return None if off == 0 else o + off

    def scalar(self, t, i, fmt, default=0):
        p = self.field(t, i)
        return default if p is None else self._u(fmt, p)

    def sub(self, t, i):
        p = self.field(t, i)
        return None if p is None else self.table(p + self._u("I", p))

    def vector(self, t, i):
        p = self.field(t, i)
        if p is None:
            return None
        v = p + self._u("I", p)
        return v + 4, self._u("I", v)

    def tables(self, t, i):
        v = self.vector(t, i)
        if not v:
            return []
        return [self.table(v[0] + 4 * k + self._u("I", v[0] + 4 * k)) for k in range(v[1])]

    def array(self, t, i, dtype):
        v = self.vector(t, i)
        if not v:
            return np.zeros(0, dtype)
        return np.frombuffer(self.b, dtype, v[1], v[0]).copy() if v[1] else np.zeros(0, dtype)

    def bytes(self, t, i):
        v = self.vector(t, i)
        return b"" if not v else self.b[v[0]:v[0] + v[1]]

    def string(self, t, i):
        return self.bytes(t, i).decode("utf-8", "replace")


def densify(fb, tensor, values, shape):
    """Dense values of a sparse tensor (SparsityParameters: traversal order,
    block map, per-dimension DENSE or SPARSE_CSR metadata)."""
    sparsity = fb.sub(tensor, 6)
    order = list(fb.array(sparsity, 0, "<i4"))
    block_map = list(fb.array(sparsity, 1, "<i4"))
    dims = fb.tables(sparsity, 2)
    rank = len(shape)
    # Extents of each traversal dimension: the tensor's dimensions, then blocks.
    extent = []
    for k, d in enumerate(dims):
        fmt = fb.scalar(d, 0, "b")
        if fmt == 0:
            extent.append(fb.scalar(d, 1, "i"))
        else:
            extent.append(None)
    out = np.zeros(shape, values.dtype)
    block_size = [1] * rank
    for k, dim in enumerate(block_map):
        block_size[dim] = extent[rank + k] if extent[rank + k] else 1

    def index_vector(d, slot):
        kind = fb.scalar(d, slot, "B")
        table = fb.sub(d, slot + 1)
        dtype = {1: "<i4", 2: "<u2", 3: "u1"}.get(kind)
        if dtype is None or table is None:
            raise ConversionError("sparse tensor with an unknown index vector")
        return fb.array(table, 0, dtype).astype(np.int64)

    segments = [None] * len(dims)
    indices = [None] * len(dims)
    for k, d in enumerate(dims):
        if fb.scalar(d, 0, "b") == 1:
            segments[k] = index_vector(d, 2)
            indices[k] = index_vector(d, 4)
    position = [0]

    def walk(level, prev, coords):
        if level == len(dims):
            index = [0] * rank
            for k, c in enumerate(coords):
                dim = order[k]
                if dim < rank:
                    index[dim] += c * block_size[dim]
                else:
                    index[block_map[dim - rank]] += c
            out[tuple(index)] = values[position[0]]
            position[0] += 1
            return
        d = dims[level]
        if fb.scalar(d, 0, "b") == 0:
            n = fb.scalar(d, 1, "i")
            for c in range(n):
                walk(level + 1, prev * n + c, coords + [c])
        else:
            seg = segments[level]
            for j in range(seg[prev], seg[prev + 1]):
                walk(level + 1, j, coords + [int(indices[level][j])])

    if len(order) != len(dims):
        raise ConversionError("sparse tensor: traversal order and dimension metadata differ")
    walk(0, 0, [])
    if position[0] != len(values):
        raise ConversionError("sparse tensor: the values do not fill its index")
    return out


class Converter:
    def __init__(self, data, input_name):
        self.fb = FlatBuffer(data)
        model = self.fb.root()
        self.buffers = self.fb.tables(model, 4)
        self.codes = []
        for oc in self.fb.tables(model, 1):
            self.codes.append(max(self.fb.scalar(oc, 0, "b"), self.fb.scalar(oc, 3, "i")))
        subgraphs = self.fb.tables(model, 2)
        if len(subgraphs) != 1:
            raise ConversionError(f"{len(subgraphs)} subgraphs; one is expected")
        self.sg = subgraphs[0]
        self.tensors = self.fb.tables(self.sg, 0)
        self.input_name = input_name
        self.nodes, self.initialisers = [], []
        self.constants = {}  # tensor index -> numpy array (folded)
        self.layout = {}     # tensor index -> "NCHW" for 4-D activations
        self.counter = 0

    def shape(self, i):
        return [int(x) for x in self.fb.array(self.tensors[i], 0, "<i4")]

    def name(self, i):
        return f"t{i}"

    def fresh(self, base):
        self.counter += 1
        return f"{base}_{self.counter}"

    def raw_constant(self, i):
        t = self.tensors[i]
        data = self.fb.bytes(self.buffers[self.fb.scalar(t, 2, "I")], 0)
        kind = self.fb.scalar(t, 1, "b")
        dtype = {FLOAT32: "<f4", FLOAT16: "<f2", INT32: "<i4"}.get(kind)
        if dtype is None:
            raise ConversionError(f"tensor {self.fb.string(t, 3)}: type {kind} is not supported")
        values = np.frombuffer(data, dtype).copy() if data else None
        return values

    def is_constant(self, i):
        return i in self.constants or self.raw_constant(i) is not None

    def constant(self, i):
        if i in self.constants:
            return self.constants[i]
        values = self.raw_constant(i)
        if values is None:
            raise ConversionError(f"tensor {self.fb.string(self.tensors[i], 3)} has no data")
        if self.fb.field(self.tensors[i], 6) is not None:
            return values  # sparse: DENSIFY shapes it
        return values.reshape(self.shape(i))

    def add_initialiser(self, name, array):
        self.initialisers.append(numpy_helper.from_array(np.ascontiguousarray(array), name))
        return name

    def activation(self, out_name, act, final):
        if act == ACT_NONE:
            return
        if act == ACT_RELU:
            self.nodes.append(helper.make_node("Relu", [out_name], [final]))
        elif act == ACT_RELU6:
            self.relu6(out_name, final)
        else:
            raise ConversionError(f"fused activation {act} is not supported")

    def relu6(self, x, out):
        lo = self.add_initialiser(self.fresh("zero"), np.array(0.0, np.float32))
        hi = self.add_initialiser(self.fresh("six"), np.array(6.0, np.float32))
        self.nodes.append(helper.make_node("Clip", [x, lo, hi], [out]))

    def emit(self, op_type, inputs, output, act=ACT_NONE, **attrs):
        target = output if act == ACT_NONE else self.fresh(output + "_pre")
        self.nodes.append(helper.make_node(op_type, inputs, [target], **attrs))
        self.activation(target, act, output)

    def same_pads(self, in_hw, out_hw, k_hw, stride, dilation):
        pads = []
        for n_in, n_out, k, s, d in zip(in_hw, out_hw, k_hw, stride, dilation):
            total = max((n_out - 1) * s + (k - 1) * d + 1 - n_in, 0)
            pads.append((total // 2, total - total // 2))
        return [pads[0][0], pads[1][0], pads[0][1], pads[1][1]]

    def convert(self):
        inputs = [int(x) for x in self.fb.array(self.sg, 1, "<i4")]
        outputs = [int(x) for x in self.fb.array(self.sg, 2, "<i4")]
        if len(inputs) != 1:
            raise ConversionError("one input is expected")
        graph_inputs = []
        for i in inputs:
            s = self.shape(i)
            graph_inputs.append(helper.make_tensor_value_info(
                self.input_name, TensorProto.FLOAT, [s[0], s[3], s[1], s[2]]))
            self.nodes.append(helper.make_node("Identity", [self.input_name], [self.name(i)]))
            self.layout[i] = "NCHW"
        for op in self.fb.tables(self.sg, 3):
            self.operator(op)
        graph_outputs = []
        for i in outputs:
            s = self.shape(i)
            out_shape = [s[0], s[3], s[1], s[2]] if len(s) == 4 else s
            name = self.fb.string(self.tensors[i], 3)
            self.nodes.append(helper.make_node("Identity", [self.name(i)], [name]))
            graph_outputs.append(helper.make_tensor_value_info(name, TensorProto.FLOAT, out_shape))
        graph = helper.make_graph(self.nodes, "converted", graph_inputs, graph_outputs,
                                  self.initialisers)
        model = helper.make_model(graph, producer_name="fvv tflite_to_onnx",
                                  opset_imports=[helper.make_opsetid("", 11)])
        model.ir_version = 6
        return model

    def operator(self, op):
        fb = self.fb
        code = self.codes[fb.scalar(op, 0, "I")]
        ins = [int(x) for x in fb.array(op, 1, "<i4")]
        outs = [int(x) for x in fb.array(op, 2, "<i4")]
        opt = fb.sub(op, 4)
        out = outs[0]
        name = self.name(out)
        if code == DEQUANTIZE:
            self.constants[out] = self.constant(ins[0]).astype(np.float32).reshape(self.shape(out))
            return
        if code == DENSIFY:
            values = self.raw_constant(ins[0])
            self.constants[out] = densify(fb, self.tensors[ins[0]], values, self.shape(out))
            return
        if code in (CONV_2D, DEPTHWISE_CONV_2D):
            w = self.constant(ins[1]).astype(np.float32)
            bias = self.constant(ins[2]).astype(np.float32) if len(ins) > 2 and ins[2] >= 0 else None
            padding = fb.scalar(opt, 0, "b")
            stride = [fb.scalar(opt, 2, "i", 1), fb.scalar(opt, 1, "i", 1)]
            if code == CONV_2D:
                act = fb.scalar(opt, 3, "b")
                dilation = [fb.scalar(opt, 5, "i", 1), fb.scalar(opt, 4, "i", 1)]
                weights = w.transpose(0, 3, 1, 2)  # OHWI -> OIHW
                group = 1
            else:
                act = fb.scalar(opt, 4, "b")
                dilation = [fb.scalar(opt, 6, "i", 1), fb.scalar(opt, 5, "i", 1)]
                weights = w.transpose(3, 0, 1, 2)  # 1HW(C*M) -> (C*M)1HW
                group = self.shape(ins[0])[3]
            k_hw = list(weights.shape[2:])
            in_s, out_s = self.shape(ins[0]), self.shape(out)
            pads = [0, 0, 0, 0] if padding == VALID else self.same_pads(
                in_s[1:3], out_s[1:3], k_hw, stride, dilation)
            wname = self.add_initialiser(self.fresh("w"), weights)
            node_in = [self.name(ins[0]), wname]
            if bias is not None:
                node_in.append(self.add_initialiser(self.fresh("b"), bias))
            self.emit("Conv", node_in, name, act, kernel_shape=k_hw, strides=stride,
                      dilations=dilation, pads=pads, group=group)
        elif code in (ADD, MUL):
            act = fb.scalar(opt, 0, "b") if opt else ACT_NONE
            operands = []
            for i in ins:
                if self.is_constant(i):
                    c = self.constant(i).astype(np.float32)
                    if c.ndim == 4:
                        c = c.transpose(0, 3, 1, 2)
                    elif c.ndim == 1 and len(self.shape(out)) == 4:
                        c = c.reshape(1, -1, 1, 1)
                    operands.append(self.add_initialiser(self.fresh("c"), c))
                else:
                    operands.append(self.name(i))
            self.emit("Add" if code == ADD else "Mul", operands, name, act)
        elif code in (MAX_POOL_2D, AVERAGE_POOL_2D):
            padding = fb.scalar(opt, 0, "b")
            stride = [fb.scalar(opt, 2, "i"), fb.scalar(opt, 1, "i")]
            k_hw = [fb.scalar(opt, 4, "i"), fb.scalar(opt, 3, "i")]
            act = fb.scalar(opt, 5, "b")
            pads = [0, 0, 0, 0] if padding == VALID else self.same_pads(
                self.shape(ins[0])[1:3], self.shape(out)[1:3], k_hw, stride, [1, 1])
            attrs = dict(kernel_shape=k_hw, strides=stride, pads=pads)
            if code == AVERAGE_POOL_2D:
                attrs["count_include_pad"] = 0
            self.emit("MaxPool" if code == MAX_POOL_2D else "AveragePool", [self.name(ins[0])],
                      name, act, **attrs)
        elif code == PAD:
            paddings = self.constant(ins[1]).astype(np.int64)  # [4, 2], NHWC
            nchw = [0, 3, 1, 2]
            pads = [int(paddings[a][0]) for a in nchw] + [int(paddings[a][1]) for a in nchw]
            pads_name = self.add_initialiser(self.fresh("pads"), np.array(pads, np.int64))
            self.emit("Pad", [self.name(ins[0]), pads_name], name, mode="constant")
        elif code == RESIZE_BILINEAR:
            align = fb.scalar(opt, 2, "B") if opt else 0
            half = fb.scalar(opt, 3, "B") if opt else 0
            mode = "align_corners" if align else "half_pixel" if half else "asymmetric"
            in_s, out_s = self.shape(ins[0]), self.shape(out)
            scales = np.array([1, 1, out_s[1] / in_s[1], out_s[2] / in_s[2]], np.float32)
            roi = self.add_initialiser(self.fresh("roi"), np.zeros(0, np.float32))
            sc = self.add_initialiser(self.fresh("scales"), scales)
            self.emit("Resize", [self.name(ins[0]), roi, sc], name, mode="linear",
                      coordinate_transformation_mode=mode)
        elif code == DEPTH_TO_SPACE:
            block = fb.scalar(opt, 0, "i")
            self.emit("DepthToSpace", [self.name(ins[0])], name, blocksize=block, mode="DCR")
        elif code == LOGISTIC:
            self.emit("Sigmoid", [self.name(ins[0])], name)
        elif code in (RELU, RELU6):
            if code == RELU:
                self.emit("Relu", [self.name(ins[0])], name)
            else:
                self.relu6(self.name(ins[0]), name)
        elif code == PRELU:
            slope = self.constant(ins[1]).astype(np.float32)
            slope = slope.reshape(-1, 1, 1) if slope.ndim >= 1 else slope
            self.emit("PRelu", [self.name(ins[0]), self.add_initialiser(self.fresh("s"), slope)],
                      name)
        elif code == RESHAPE:
            src = self.name(ins[0])
            if len(self.shape(ins[0])) == 4:
                nhwc = self.fresh("nhwc")
                self.nodes.append(helper.make_node("Transpose", [src], [nhwc], perm=[0, 2, 3, 1]))
                src = nhwc
            new_shape = np.array(self.shape(out), np.int64)
            shape_name = self.add_initialiser(self.fresh("shape"), new_shape)
            if len(new_shape) == 4:
                tmp = self.fresh("reshaped")
                self.nodes.append(helper.make_node("Reshape", [src, shape_name], [tmp]))
                self.emit("Transpose", [tmp], name, perm=[0, 3, 1, 2])
            else:
                self.emit("Reshape", [src, shape_name], name)
        elif code == CONCATENATION:
            axis = fb.scalar(opt, 0, "i")
            act = fb.scalar(opt, 1, "b")
            rank = len(self.shape(out))
            if axis < 0:
                axis += rank
            if rank == 4:
                axis = [0, 2, 3, 1][axis]
            self.emit("Concat", [self.name(i) for i in ins], name, act, axis=axis)
        else:
            raise ConversionError(f"operator {NAMES.get(code, code)} is not supported")


def clip_bounds_as_attributes(model):
    """Clip(x, min, max) -> Clip(x) with min/max attributes, as OpenCV 4.6 reads it."""
    constants = {t.name: numpy_helper.to_array(t) for t in model.graph.initializer}
    used = set()
    for node in model.graph.node:
        if node.op_type == "Clip" and len(node.input) == 3:
            lo, hi = float(constants[node.input[1]]), float(constants[node.input[2]])
            used.update(node.input[1:])
            del node.input[1:]
            node.attribute.extend([helper.make_attribute("min", lo),
                                   helper.make_attribute("max", hi)])
    keep = [t for t in model.graph.initializer if t.name not in used]
    del model.graph.initializer[:]
    model.graph.initializer.extend(keep)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("model")
    parser.add_argument("output")
    parser.add_argument("--input-name", default="input")
    args = parser.parse_args()
    try:
        with open(args.model, "rb") as f:
            data = f.read()
        model = Converter(data, args.input_name).convert()
        onnx.checker.check_model(model)
        clip_bounds_as_attributes(model)
    except (ConversionError, OSError, onnx.checker.ValidationError) as e:
        print(f"tflite_to_onnx: {args.model}: {e}", file=sys.stderr)
        return 1
    temp = args.output + ".part"
    onnx.save(model, temp)
    import os
    os.replace(temp, args.output)
    print(f"tflite_to_onnx: {args.model} -> {args.output} ({len(model.graph.node)} nodes)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
