"""The simulator keeps the answers of repeated reads (a polling client's hot path) only while they hold.

A kept answer is used only while the device's memory is unchanged since it was worked out: every write,
command effect and value that changes on being read moves `DeviceStore.generation`. These tests look
at what a client sees, and at the counters, after each kind of change.
"""

from __future__ import annotations

import asyncio
import contextlib
import io
import socket
import struct

import pytest

from regmap.frontend import load_map
from regmap.tools.simulator.connection import Poller, TcpConnection
from regmap.tools.simulator.faults import FaultPlan
from regmap.tools.simulator.log import RequestLog
from regmap.tools.simulator.server import Simulator

from conftest import ROOT, SimulatorFactory

IDM = load_map(ROOT / "maps" / "idm_rs.yaml")
PEAK = IDM.register("peak_current")
CONTROL = IDM.register("control_word")
SAVE_STATUS = IDM.register("save_status")


def mbap(transaction: int, unit: int, pdu: bytes) -> bytes:
    return struct.pack(">HHHB", transaction, 0, len(pdu) + 1, unit) + pdu


def read(address: int, count: int = 1) -> bytes:
    return struct.pack(">BHH", 0x03, address, count)


def write(address: int, word: int) -> bytes:
    return struct.pack(">BHH", 0x06, address, word)


def command_value(name: str) -> int:
    command = next(c for c in IDM.commands if c.name == name)
    assert isinstance(command.value, int)
    return command.value


class Client:
    """Requests straight into an in-process simulator; the answers it sent, in order."""

    def __init__(self, sim: Simulator) -> None:
        self.sim = sim
        self.sent: list[bytes] = []
        self.transaction = 0

    def ask(self, pdu: bytes, unit: int = 1) -> bytes:
        self.transaction += 1
        self.sim.tcp_frame(mbap(self.transaction, unit, pdu), self.sent.append, "test")
        answer = self.sent[-1]
        assert answer[:2] == struct.pack(">H", self.transaction)  # each answer carries its own request's transaction id
        return answer[7:]

    def word(self, address: int, unit: int = 1) -> int:
        answer = self.ask(read(address), unit)
        assert answer[:2] == b"\x03\x02", answer.hex()
        return int(struct.unpack(">H", answer[2:4])[0])


def test_a_kept_read_follows_each_write_and_each_command_effect() -> None:
    sim = Simulator(IDM, 1)
    client = Client(sim)
    default = client.word(PEAK.address)
    assert client.word(PEAK.address) == default and len(sim.answers) == 1  # the second one was kept
    assert client.ask(write(PEAK.address, default + 1)) == write(PEAK.address, default + 1)
    assert client.word(PEAK.address) == default + 1
    assert client.word(PEAK.address, unit=0xFF) == default + 1  # the device addressed directly: its own kept answer
    client.ask(write(CONTROL.address, command_value("restore_factory_defaults")))
    assert client.word(PEAK.address) == default
    assert client.word(PEAK.address, unit=0xFF) == default


def test_a_value_that_changes_on_being_read_is_read_fresh_each_time() -> None:
    sim = Simulator(IDM, 1)
    client = Client(sim)
    client.word(SAVE_STATUS.address)  # kept before the save
    client.ask(write(CONTROL.address, command_value("save_all_parameters")))
    assert [client.word(SAVE_STATUS.address) for _ in range(3)] == [0x5555, 0x1111, 0x1111]


def test_kept_answers_are_counted_as_answers_and_exceptions() -> None:
    sim = Simulator(IDM, 1)
    client = Client(sim)
    undocumented = max(r.last_address for r in IDM.registers if r.space == "holding") + 1
    for _ in range(3):
        assert client.ask(read(undocumented)) == bytes([0x83, 0x02])
        client.word(PEAK.address)
    stats = sim.stats
    assert (stats.frames_received, stats.frames_sent, stats.exceptions_sent) == (6, 6, 3)
    assert stats.bytes_sent == sum(map(len, client.sent)) and list(stats.requests)[-1][:2] == struct.pack(">H", 6)


def test_a_request_log_and_injected_faults_see_every_request() -> None:
    stream = io.StringIO()
    sim = Simulator(IDM, 1, log=RequestLog(IDM, [stream]))
    client = Client(sim)
    client.word(PEAK.address)
    client.word(PEAK.address)
    assert stream.getvalue().count("peak_current") >= 2 and len(sim.answers) == 0
    faulty = Simulator(IDM, 1, faults=FaultPlan("exception", count=1))
    client = Client(faulty)
    assert client.ask(read(PEAK.address))[0] == 0x83  # the fault takes the first answer ...
    assert client.ask(read(PEAK.address))[:2] == b"\x03\x02"  # ... and only the first


def test_a_write_on_one_connection_is_seen_by_the_next_read_on_another(simulator: SimulatorFactory) -> None:
    sim = simulator(ROOT / "maps" / "idm_rs.yaml")
    assert sim.port is not None
    with (
        socket.create_connection(("127.0.0.1", sim.port), timeout=5) as poller,
        socket.create_connection(("127.0.0.1", sim.port), timeout=5) as writer,
    ):
        answers = []
        for transaction, value in enumerate((11, 12, 13), start=1):
            poller.sendall(mbap(transaction, 1, read(PEAK.address)))
            answers.append(poller.recv(64))
            writer.sendall(mbap(transaction, 1, write(PEAK.address, value)))
            assert writer.recv(64) == mbap(transaction, 1, write(PEAK.address, value))
        poller.sendall(mbap(9, 1, read(PEAK.address)))
        answers.append(poller.recv(64))
    words = [struct.unpack(">H", a[9:11])[0] for a in answers]
    assert words[1:] == [11, 12, 13]


def in_process_connection(sim: Simulator, use_epoll: bool) -> tuple[TcpConnection, socket.socket]:
    """A connection of `sim` (its sockets watched by one epoll, or each by the event loop) and its client's side."""
    if sim.poller is None:
        sim.poller = Poller(asyncio.get_running_loop(), use_epoll=use_epoll)
    server_side, client_side = socket.socketpair()
    server_side.setblocking(False)
    client_side.setblocking(False)
    connection = TcpConnection(sim, False, server_side, ("client", 1))
    connection.start()
    return connection, client_side


async def read_answers(client_side: socket.socket, want: int) -> bytes:
    got = b""
    for _ in range(300):
        with contextlib.suppress(BlockingIOError):
            got += client_side.recv(4096)
        if len(got) >= want:
            break
        await asyncio.sleep(0.005)
    return got


@pytest.mark.parametrize("use_epoll", [True, False], ids=["epoll", "event-loop"])
def test_a_client_that_does_not_read_its_answers_is_not_read_until_it_does(use_epoll: bool) -> None:
    """Answers a client has not taken wait in the connection; meanwhile it is not read (its requests wait in
    the socket), and once it reads, every answer arrives once, in order."""
    total = 3000
    requests = b"".join(mbap(t, 1, read(PEAK.address)) for t in range(total))

    async def scenario() -> tuple[int, bool, bytes]:
        sim = Simulator(IDM, 1)
        sim.poller = Poller(asyncio.get_running_loop(), use_epoll=use_epoll)
        server_side, client_side = socket.socketpair()
        for sock, option in ((server_side, socket.SO_SNDBUF), (client_side, socket.SO_RCVBUF)):
            sock.setsockopt(socket.SOL_SOCKET, option, 4096)
            sock.setblocking(False)
        connection = TcpConnection(sim, False, server_side, ("client", 1))
        connection.start()
        pending = memoryview(requests)
        held = False
        for _ in range(200):  # send without reading, until the simulator holds answers back
            with contextlib.suppress(BlockingIOError):
                pending = pending[client_side.send(pending) :]
            await asyncio.sleep(0.005)
            if connection.unsent:
                held = True
                break
        received_while_held = sim.stats.frames_received
        await asyncio.sleep(0.05)
        held = held and sim.stats.frames_received == received_while_held  # no request read while answers wait
        answers = b""
        for _ in range(2000):  # now read, sending the rest
            with contextlib.suppress(BlockingIOError):
                answers += client_side.recv(65536)
            if pending:
                with contextlib.suppress(BlockingIOError):
                    pending = pending[client_side.send(pending) :]
            if len(answers) >= total * 11:
                break
            await asyncio.sleep(0.002)
        connection.close()
        client_side.close()
        return received_while_held, held, answers

    received_while_held, held, answers = asyncio.run(scenario())
    assert held and received_while_held < total
    assert len(answers) == total * 11
    transactions = [struct.unpack_from(">H", answers, 11 * i)[0] for i in range(total)]
    assert transactions == list(range(total))
    assert all(answers[11 * i + 2 : 11 * i + 9] == bytes([0, 0, 0, 5, 1, 0x03, 2]) for i in range(total))  # each a whole answer


def test_a_write_whose_data_looks_like_a_repeated_read_is_a_write() -> None:
    """A request cut across segments: its last one equals a kept read after a transaction id (the written words
    spell that read), and is still the tail of the write, not a read answered from the answer cache."""
    values = [0x1234, *struct.unpack(">5H", mbap(0, 1, read(PEAK.address))[2:])]
    pdu = struct.pack(">BHHB6H", 0x10, PEAK.address, len(values), 2 * len(values), *values)
    request = mbap(7, 1, pdu)

    async def scenario() -> tuple[bytes, bytes]:
        sim = Simulator(IDM, 1)
        connection, client_side = in_process_connection(sim, use_epoll=True)
        client_side.send(mbap(1, 1, read(PEAK.address)))
        kept = await read_answers(client_side, 11)
        client_side.send(request[:-12])
        await asyncio.sleep(0.05)
        client_side.send(request[-12:])
        got = await read_answers(client_side, 12)
        connection.close()
        client_side.close()
        return kept, got

    kept, got = asyncio.run(scenario())
    assert kept[7:9] == b"\x03\x02"
    assert got[:2] == struct.pack(">H", 7) and got[7] & 0x7F == 0x10, got.hex()


@pytest.mark.parametrize("use_epoll", [True, False], ids=["epoll", "event-loop"])
def test_a_connection_after_a_closed_one_is_served_on_the_same_descriptor(use_epoll: bool) -> None:
    async def scenario() -> tuple[list[int], list[bytes]]:
        sim = Simulator(IDM, 1)
        descriptors, got = [], []
        for transaction in (1, 2):
            connection, client_side = in_process_connection(sim, use_epoll)
            descriptors.append(connection.fd)
            client_side.send(mbap(transaction, 1, read(PEAK.address)))
            got.append(await read_answers(client_side, 11))
            client_side.close()  # the simulator closes its side on reading the end
            for _ in range(100):
                if connection.closed:
                    break
                await asyncio.sleep(0.005)
        assert sim.poller is not None
        sim.poller.close()
        return descriptors, got

    descriptors, (first, second) = asyncio.run(scenario())
    assert descriptors[0] == descriptors[1]
    assert first[:2] == struct.pack(">H", 1) and second[:2] == struct.pack(">H", 2) and first[2:] == second[2:]
